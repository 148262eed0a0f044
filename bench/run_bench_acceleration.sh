#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# SMACOF's accelerations side by side (bench/bench_acceleration.cpp): the Euclidean canonical form
# (variant N; variant A at 2k and 10k) of procedural figures in several poses at 2k-200k vertices, of TOSCA and FAUST
# (DATA/tosca_r5k, DATA/faust_r5k, with labels.csv and corres/), and least-squares MDS of a 2000-vertex
# figure's geodesic distances, every method on every mesh interleaved. Writes
# bench/results/acceleration.{csv,md} and the docs' picture docs/images/bench_acceleration.png.
#   bench/run_bench_acceleration.sh [DATA]     (default DATA: /work/data; skipped if absent)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
data=${1:-/work/data}
[ -x "$build/bench/canonform_bench_acceleration" ] || CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
out="$here/bench/results"; mkdir -p "$out"
export OMP_NUM_THREADS=1
b="$build/bench/canonform_bench_acceleration"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
taskset -c 0 "$b" --sizes 2000,10000 --poses 6 --repeats 3 --csv "$tmp/1.csv" > "$tmp/1.md"
taskset -c 0 "$b" --sizes 50000 --poses 3 --repeats 1 --csv "$tmp/2.csv" > "$tmp/2.md"
taskset -c 0 "$b" --sizes 200000 --poses 2 --repeats 1 --csv "$tmp/3.csv" > "$tmp/3.md"
taskset -c 0 "$b" --variant A --sizes 2000,10000 --poses 6 --repeats 1 --csv "$tmp/3a.csv" > "$tmp/3a.md"
if [ -d "$data/tosca_r5k" ] && [ -d "$data/faust_r5k" ]; then
  taskset -c 0 "$b" --dataset "$data/tosca_r5k" --labels "$data/tosca_r5k/labels.csv" --name tosca_r5k \
    --dataset "$data/faust_r5k" --labels "$data/faust_r5k/labels.csv" --name faust_r5k --csv "$tmp/4.csv" > "$tmp/4.md"
fi
taskset -c 0 "$b" --geodesic 2000 --repeats 3 --csv "$tmp/5.csv" > "$tmp/5.md"
head -2 "$tmp/1.md" > "$out/acceleration.md"; head -1 "$tmp/1.csv" > "$out/acceleration.csv"
for f in "$tmp"/*.md; do tail -n +3 "$f" >> "$out/acceleration.md"; done
for f in "$tmp"/*.csv; do tail -n +2 "$f" >> "$out/acceleration.csv"; done
/usr/bin/python3 "$here/bench/plot_acceleration.py" "$out/acceleration.csv" "$here/docs/images/bench_acceleration.png"
