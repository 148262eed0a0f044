#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The 600 x 10k plan as one whole timed run (docs/benchmarks.md, "600 meshes of 10k vertices"): a
# generated collection of 600 figures of 10k vertices (six body types x 100 random poses), then
# `canonform retrieve --method euclidean-N --threads 2` from an empty run folder, timed by GNU time:
# wall and CPU seconds, peak memory, and the run's own stage timings. Writes one JSON line with the
# machine's load before and after to bench/results/retrieve_600.jsonl (replaced only on success).
#   bench/run_retrieve_600.sh [BUILD_DIR [WORK_DIR]]     (WORK_DIR keeps the collection between runs)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
work=${2:-$(mktemp -d)}
[ -n "${2:-}" ] || trap 'rm -rf "$work"' EXIT
cf=$build/apps/canonform
[ -x "$cf" ] || { echo "run_retrieve_600.sh: no $cf (tools/build.sh first)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "run_retrieve_600.sh: GNU time missing (Debian package time)" >&2; exit 1; }
[ -f "$work/c600/labels.csv" ] || "$cf" generate --collection "$work/c600" --vertices 10000 --poses 100 > /dev/null
rm -rf "$work/run"
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
/usr/bin/time -f '%e %U %S %M' -o "$work/time.txt" \
  "$cf" retrieve --dataset "$work/c600" --out "$work/run" --method euclidean-N --threads 2 > "$work/run.out" 2> "$work/run.err" ||
  { tail -5 "$work/run.err" >&2; exit 1; }
read -r wall user sys rss < "$work/time.txt"
out=$here/bench/results/retrieve_600.jsonl
/usr/bin/python3 - "$work/run/euclidean-N/timings.json" "$wall" "$user" "$sys" "$rss" "$load_before" \
    "$(cut -d' ' -f1-3 /proc/loadavg)" "$(git -C "$here" rev-parse --short HEAD)" "$(nproc)" \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)" > "$out.tmp" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["seconds"]
wall, user, sys_s, rss = float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
print(json.dumps({"load_before": sys.argv[6], "build": sys.argv[8], "cpus": int(sys.argv[9]), "cpu": sys.argv[10]}))
print(json.dumps({"bench": "retrieve_600", "models": 600, "vertices": 10000, "method": "euclidean-N", "threads": 2,
                  "wall_s": wall, "cpu_s": round(user + sys_s, 1), "wall_min": round(wall / 60, 2),
                  "peak_rss_mib": round(rss / 1024), "forms_and_views_s": round(t["forms_and_views"], 1),
                  "codebook_s": round(t["codebook"], 1), "distances_and_measures_s": round(t["distances_and_measures"], 1)}))
print(json.dumps({"load_after": sys.argv[7]}))
PY
mv "$out.tmp" "$out"
cat "$out"
