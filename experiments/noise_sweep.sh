#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The paper's Table 5 (retrieval under vertex noise): `canonform retrieve --noise SIGMA` for each
# sigma (Gaussian noise on every coordinate, sigma x the mean edge length of the mesh as retrieved,
# i.e. after --simplify; seeded by --seed and the mesh), then experiments/plot_noise.py.
#   experiments/noise_sweep.sh DATASET OUT [--sigmas "0 0.1 0.2 0.4"] [retrieve options, e.g. --method ... --simplify 1000]
# Writes OUT/sigma_S/ (one run per sigma), OUT/noise.csv and OUT/noise.png.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cf=${CANONFORM:-$here/build/apps/canonform}
dataset=$1 out=$2
shift 2
sigmas="0 0.1 0.2 0.4"
if [ "${1:-}" = "--sigmas" ]; then sigmas=$2; shift 2; fi
mkdir -p "$out"
args=()
for s in $sigmas; do
  echo "== sigma $s ($(date -u +%T))" >&2
  "$cf" retrieve --dataset "$dataset" --out "$out/sigma_$s" --noise "$s" "$@" > "$out/sigma_$s.md"
  args+=("$s=$out/sigma_$s")
done
/usr/bin/python3 "$here/experiments/plot_noise.py" "$out/noise" "${args[@]}"
