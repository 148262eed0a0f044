#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The shape of the paper's Table 1 and Fig. 7: one articulated figure (16k vertices, pose 1)
# simplified by quadric edge collapse to about 1k, 2k, 4k and 8k vertices (and generated at 50k
# and 200k for the Euclidean method only); time and peak memory of Euclidean A and N and of
# geodesic C, F and LS, each method and size in its own process, all on one core, in one run.
# Writes bench/results/table1.{jsonl,md} and docs/images/bench_table1.png. Takes about 10-15 minutes.
#   bench/run_table1.sh [--quick]        (--quick: 1k and 2k only)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
[ -x "$build/bench/canonform_bench_canonical" ] || CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
cf="$build/apps/canonform"; bench="$build/bench/canonform_bench_canonical"
out="$here/bench/results"; cache="$build/bench_meshes"
mkdir -p "$out" "$cache"
geo_sizes=(1000 2000 4000 8000 16000); euc_only=(50000 200000)
if [ "${1:-}" = "--quick" ]; then geo_sizes=(1000 2000); euc_only=(); fi
[ -f "$cache/t1_16000.ply" ] || "$cf" generate "$cache/t1_16000.ply" --vertices 16000 --pose 1
for n in "${geo_sizes[@]}"; do
  [ "$n" = 16000 ] || [ -f "$cache/t1_$n.ply" ] || "$cf" simplify "$cache/t1_16000.ply" "$cache/t1_$n.ply" --vertices "$n" 2>/dev/null
done
for n in "${euc_only[@]}"; do
  [ -f "$cache/t1_$n.ply" ] || "$cf" generate "$cache/t1_$n.ply" --vertices "$n" --pose 1
done
raw="$out/table1.jsonl"; : > "$raw"
run() { taskset -c 0 "$bench" "$@" | tee -a "$raw"; }
for n in "${geo_sizes[@]}"; do
  mesh="$cache/t1_$n.ply"
  run "$mesh" --variant A --repeats 5
  run "$mesh" --variant N --repeats 5
  reps=3; [ "$n" -ge 4000 ] && reps=1
  for m in geodesic-fast geodesic-classical geodesic-ls; do run "$mesh" --method $m --repeats $reps --threads 1; done
done
for n in "${euc_only[@]}"; do
  run "$cache/t1_$n.ply" --variant A --repeats 3
  run "$cache/t1_$n.ply" --variant N --repeats 3
done
/usr/bin/python3 "$here/bench/report_table1.py" "$raw" "$out/table1.md" "$here/docs/images/bench_table1.png"
