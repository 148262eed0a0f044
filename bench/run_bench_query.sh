#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Two-stage queries (first pass + exact clock matching) against exhaustive ones (docs/scale.md),
# through bench_query; JSON lines with the machine's load before and after.
#   bench/run_bench_query.sh synthetic BUILD_DIR REAL [MODELS] [QUERIES] [BENCH OPTIONS...]
#     REAL: the method folder of a retrieval run whose histograms make the synthetic index (the
#     figures in docs/scale.md: `canonform retrieve --method euclidean-N` over the union of TOSCA,
#     FAUST and SHREC'07 half). MODELS (default 10^5) models, QUERIES (default 1000) queries;
#     writes bench/results/bench_query.jsonl (bench_query_MODELS.jsonl for another size).
#   bench/run_bench_query.sh collections BUILD_DIR METHOD_FOLDER...
#     every member of each real collection as a query; writes bench/results/bench_query_collections.jsonl.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mode=${1:?synthetic or collections}
build=${2:?build folder}
shift 2
bench=$build/bench/canonform_bench_query
load() { cut -d' ' -f1-3 /proc/loadavg; }
run() {
  local out=$1
  shift
  {
    echo "{\"load_before\": \"$(load)\", \"cpus\": $(nproc), \"cpu\": \"$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)\"}"
    "$bench" "$@"
    echo "{\"load_after\": \"$(load)\"}"
  } | tee "$out.tmp"
  mv "$out.tmp" "$out"
}
case $mode in
  synthetic)
    real=${1:?the real method folder}
    models=${2:-100000}
    queries=${3:-1000}
    shift $(($# < 3 ? $# : 3))
    name=bench_query
    [ "$models" = 100000 ] || name=bench_query_$models
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    run "$here/bench/results/$name.jsonl" synthetic "$real" --models "$models" --queries "$queries" \
      --candidates 250,500,750,1000,1500,2000,4000 --latency-queries 20 --threads 2 --save "$work" "$@"
    ;;
  collections)
    run "$here/bench/results/bench_query_collections.jsonl" collection "$@" --candidates 10,15,20,30,50,100,150,200 --threads 2
    ;;
  *) echo "run_bench_query.sh: synthetic or collections, not $mode" >&2; exit 2 ;;
esac
