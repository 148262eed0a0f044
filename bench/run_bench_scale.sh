#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The whole `canonform canonical` (Euclidean, variant N, defaults) of procedural figures of 200k and
# 1M vertices (`canonform generate --vertices N`, pose 0), as a user runs it: wall and CPU seconds
# (user + system, from /usr/bin/time), the time split by stage (read + validation, conformal
# factor, setup, SMACOF, write; from --json), peak RSS and minor page faults, medians of R runs.
# With BASELINE (another build's canonform), both binaries run interleaved in one run, side by
# side, and the printed table adds the final stress and the wall time relative to the baseline's.
# Writes bench/results/canonical_scale.jsonl (the docs' table) and prints the table.
#   bench/run_bench_scale.sh [--repeats R] [--sizes 200000,1000000] [--baseline BASELINE]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
repeats=3; sizes=200000,1000000; baseline=""
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --baseline) baseline=$2; shift 2 ;;
    *) echo "usage: $0 [--repeats R] [--sizes N,...] [--baseline CANONFORM]" >&2; exit 2 ;;
  esac
done
[ -x "$build/apps/canonform" ] || CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
out="$here/bench/results"; cache="$build/bench_meshes"; mkdir -p "$out" "$cache"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
raw="$out/canonical_scale.jsonl"; : > "$raw"
binaries=("this:$build/apps/canonform")
[ -n "$baseline" ] && binaries+=("baseline:$baseline")
IFS=, read -r -a size_list <<< "$sizes"
for n in "${size_list[@]}"; do
  mesh="$cache/figure_${n}_pose0.ply"
  [ -f "$mesh" ] || "$build/apps/canonform" generate "$mesh" --vertices "$n" --pose 0 > /dev/null
  for ((r = 0; r < repeats; r++)); do
    for entry in "${binaries[@]}"; do
      name=${entry%%:*}; bin=${entry#*:}
      /usr/bin/time -f '{"wall_s": %e, "user_s": %U, "system_s": %S, "peak_rss_kib": %M, "minor_faults": %R}' \
        -o "$tmp/time.json" "$bin" canonical "$mesh" "$tmp/out.ply" --json > "$tmp/run.json"
      /usr/bin/python3 -c 'import json, sys
j = json.load(open(sys.argv[1])); j.update(json.load(open(sys.argv[2])))
j["binary"] = sys.argv[3]; j["run"] = int(sys.argv[4]); print(json.dumps(j))' \
        "$tmp/run.json" "$tmp/time.json" "$name" "$r" | tee -a "$raw"
    done
  done
done
/usr/bin/python3 "$here/bench/report_scale.py" "$raw"
