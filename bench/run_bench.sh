#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Benchmark of the Euclidean canonical form at about 2k, 10k, 50k and 200k vertices (procedural
# figures, pose 1), single-threaded, medians of several runs measured in one run: variant N with
# each of SMACOF's two linear solvers side by side (direct LDL^T factor, AMG V-cycle), both
# variants. The report adds the default "auto" (direct below 40k vertices, multigrid from there:
# SmacofSolverOptions::multigrid_from in src/canonform/numerics/smacof.h). Writes
# bench/results/canonical_form.{jsonl,md} and the docs' picture docs/images/bench_canonical_form.png.
#   bench/run_bench.sh [--quick]        (--quick: 2k and 10k only, 3 repeats)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
[ -x "$build/bench/canonform_bench_canonical" ] || CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
out="$here/bench/results"; cache="$build/bench_meshes"
mkdir -p "$out" "$cache"
sizes=(2000 10000 50000 200000); repeats=(7 5 5 3)
if [ "${1:-}" = "--quick" ]; then sizes=(2000 10000); repeats=(3 3); fi
export OMP_NUM_THREADS=1
raw="$out/canonical_form.jsonl"; : > "$raw"
for k in "${!sizes[@]}"; do
  n=${sizes[$k]}
  mesh="$cache/figure_${n}.ply"
  [ -f "$mesh" ] || "$build/apps/canonform" generate "$mesh" --vertices "$n" --pose 1
  for run in "N direct" "N multigrid" "A direct" "A multigrid"; do
    set -- $run
    taskset -c 0 "$build/bench/canonform_bench_canonical" "$mesh" --variant "$1" --solver "$2" \
      --repeats "${repeats[$k]}" | tee -a "$raw"
  done
done
/usr/bin/python3 "$here/bench/report.py" "$raw" "$out/canonical_form.md" "$here/docs/images/bench_canonical_form.png" \
  --auto-from 40000
