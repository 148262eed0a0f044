#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Two builds' canonform_bench_canonical on one mesh, side by side: RUNS processes of each, the two
# binaries alternating so that both see the same machine; each process times R runs of the method
# in-process (the mesh read once) and reports their median.
#   bench/run_canonical_side_by_side.sh OUT.jsonl RUNS OLD_LABEL OLD_BENCH NEW_LABEL NEW_BENCH MESH [ARGS...]
# ARGS go to both benchmarks (default --repeats 11; e.g. --variant A, --method NAME).
# OUT.jsonl: a header line (date, load, cores, the two labels), then one line per process
# ({"bench": "canonical", "build", "median_s", "min_s", "iterations", "peak_mib"}); the script prints
# each build's median over its processes and the ratio NEW / OLD.
set -euo pipefail
[ $# -ge 7 ] || { sed -n 3,10p "$0" >&2; exit 2; }
out=$1 runs=$2 old_label=$3 old_bench=$4 new_label=$5 new_bench=$6 mesh=$7
shift 7
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(--repeats 11)
for b in "$old_bench" "$new_bench"; do [ -x "$b" ] || { echo "not an executable: $b" >&2; exit 2; }; done
[ -f "$mesh" ] || { echo "no such mesh: $mesh" >&2; exit 2; }
cpu=$(grep -m1 "model name" /proc/cpuinfo | sed 's/.*: //')
python3 -c 'import json, sys; print(json.dumps({"date": sys.argv[1], "load_before": sys.argv[2], "cpus": int(sys.argv[3]),
    "cpu": sys.argv[4], "builds": [sys.argv[5], sys.argv[6]]}))' \
  "$(date -u +%FT%TZ)" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(nproc)" "$cpu" "$old_label" "$new_label" > "$out"
for ((i = 0; i < runs; i++)); do
  for pair in "$old_label=$old_bench" "$new_label=$new_bench"; do
    label=${pair%%=*} bench=${pair#*=}
    "$bench" "$mesh" "${args[@]}" | python3 -c 'import json, sys
r = json.loads(sys.stdin.read())
print(json.dumps({"bench": "canonical", "build": sys.argv[1], "median_s": r["median_s"], "min_s": r["min_s"],
                  "iterations": r["iterations"], "peak_mib": r["peak_mib"]}))' "$label" >> "$out"
  done
done
python3 - "$out" "$old_label" "$new_label" <<'EOF'
import json, statistics, sys
rows = [json.loads(x) for x in open(sys.argv[1]) if '"bench"' in x]
med = {b: statistics.median(r["median_s"] for r in rows if r["build"] == b) for b in sys.argv[2:4]}
for b, m in med.items():
    print(f"{b}: median {m:.4f} s over {sum(r['build'] == b for r in rows)} processes")
print(f"ratio {med[sys.argv[3]] / med[sys.argv[2]]:.3f}")
EOF
