#!/usr/bin/env bash
# Per-stage costs for the 600-mesh plan (README, "600 meshes of 10k vertices"): six procedural
# figures of 10k vertices (six body types, six poses) through bench_600, which prints wall and CPU
# seconds per stage as JSON lines (bench/results/bench_600.jsonl) with the machine's load.
#   bench/run_bench_600.sh [BUILD_DIR [bench_600 options, e.g. --sift opencv-half]]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$here/bench/six_figures.sh"
six_figures "$build" "$work"
out=$here/bench/results/bench_600.jsonl
{
  echo "{\"load_before\": \"$(cut -d' ' -f1-3 /proc/loadavg)\", \"cpus\": $(nproc), \"date\": \"$(date -u +%FT%TZ)\"}"
  "$build/bench/canonform_bench_600" "$work"/*.ply "${@:2}"
  echo "{\"load_after\": \"$(cut -d' ' -f1-3 /proc/loadavg)\"}"
} | tee "$out.tmp"
mv "$out.tmp" "$out"
