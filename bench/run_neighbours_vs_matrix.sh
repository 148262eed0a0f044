#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Evaluation without the matrix against the matrix (docs/scale.md): for each collection, one
# `canonform retrieve` (the N x N matrix) and one sharded run with --evaluation neighbours (each
# model's K nearest through the index), method euclidean-N, default options; prints one JSON line
# per collection with both runs' measures and whether they are equal (NN, tiers, E-measure exactly;
# DCG within the truncation bound), into bench/results/neighbours_vs_matrix.jsonl.
#   bench/run_neighbours_vs_matrix.sh BUILD_DIR WORK DATASET...
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:?build folder}
work=${2:?work folder}
shift 2
cf=$build/apps/canonform
out=$here/bench/results/neighbours_vs_matrix.jsonl
mkdir -p "$work"
for data in "$@"; do
  name=$(basename "$data")
  [ -s "$work/matrix_$name/euclidean-N/metrics.json" ] ||
    "$cf" retrieve --dataset "$data" --out "$work/matrix_$name" --method euclidean-N --threads 2 > /dev/null
  if [ ! -s "$work/nb_$name/euclidean-N/metrics.json" ]; then
    rm -rf "$work/nb_$name"
    "$cf" stage init --dataset "$data" --out "$work/nb_$name" --method euclidean-N --evaluation neighbours
    "$cf" stage all "$work/nb_$name" --threads 2 2> /dev/null
  fi
done
for data in "$@"; do
  name=$(basename "$data")
  /usr/bin/python3 - "$name" "$work/matrix_$name/euclidean-N/metrics.json" "$work/nb_$name/euclidean-N/metrics.json" <<'PY'
import json, sys
name, a, b = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
exact = ["nn", "first_tier", "second_tier", "e_measure", "queries"]
row = {"collection": name, "models": a["meshes"], "neighbours": b["neighbours"], "search": b["search"]}
for avg in ("micro", "macro"):
    for k in exact + ["dcg"]:
        row[f"{avg}_{k}_matrix"], row[f"{avg}_{k}_neighbours"] = a[avg][k], b[avg][k]
bound = b["dcg_bound"]
row["dcg_bound_micro"], row["dcg_bound_macro"] = bound["micro"], bound["macro"]
row["exact_measures_equal"] = all(a[m][k] == b[m][k] for m in ("micro", "macro") for k in exact)
row["dcg_within_bound"] = all(b[m]["dcg"] <= a[m]["dcg"] <= b[m]["dcg"] + bound[m] + 1e-12 for m in ("micro", "macro"))
print(json.dumps(row))
PY
done | tee "$out.tmp"
mv "$out.tmp" "$out"
