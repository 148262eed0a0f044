#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Query latency against an index of 10^5 models (docs/scale.md): six procedural
# figures of 10k vertices (six body types) through bench_query, which repeats their real
# histograms to 10^5 models and prints the index build and the top-10 query latency as JSON
# lines (bench/results/bench_query.jsonl) with the machine's load.
#   bench/run_bench_query.sh [BUILD_DIR] [MODELS]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
. "$here/bench/six_figures.sh"
bench_jsonl "$build" "$here/bench/results/bench_query.jsonl" "$build/bench/canonform_bench_query" --models "${2:-100000}"
