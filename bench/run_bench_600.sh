#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Per-stage costs for the 600-mesh plan (docs/benchmarks.md, "600 meshes of 10k vertices"): six procedural
# figures of 10k vertices (six body types, six poses) through bench_600, which prints wall and CPU
# seconds per stage as JSON lines (bench/results/bench_600.jsonl) with the machine's load.
#   bench/run_bench_600.sh [BUILD_DIR [bench_600 options, e.g. --sift opencv-half]]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
. "$here/bench/six_figures.sh"
bench_jsonl "$build" "$here/bench/results/bench_600.jsonl" "$build/bench/canonform_bench_600" "${@:2}"
