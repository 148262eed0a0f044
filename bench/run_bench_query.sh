#!/usr/bin/env bash
# Query latency against an index of 10^5 models (README, "Beyond one machine"): six procedural
# figures of 10k vertices (six body types) through bench_query, which repeats their real
# histograms to 10^5 models and prints the index build and the top-10 query latency as JSON
# lines (bench/results/bench_query.jsonl) with the machine's load.
#   bench/run_bench_query.sh [BUILD_DIR] [MODELS]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
models=${2:-100000}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$here/bench/six_figures.sh"
six_figures "$build" "$work"
out=$here/bench/results/bench_query.jsonl
{
  echo "{\"load_before\": \"$(cut -d' ' -f1-3 /proc/loadavg)\", \"cpus\": $(nproc), \"date\": \"$(date -u +%FT%TZ)\", \"cpu\": \"$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)\"}"
  "$build/bench/canonform_bench_query" "$work"/*.ply --models "$models"
  echo "{\"load_after\": \"$(cut -d' ' -f1-3 /proc/loadavg)\"}"
} | tee "$out.tmp"
mv "$out.tmp" "$out"
