#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The paper's Fig. 6: retrieval with the Euclidean canonical forms over a range of beta, both
# variants, and the mean of the five measures against beta.
#   experiments/beta_sweep.sh DATASET RUN [--betas-a "B ..."] [--betas-n "B ..."] [retrieve options...]
# DATASET holds labels.csv; RUN is the run folder (its cache makes a re-run or added betas cheap).
# Runs `canonform retrieve --method euclidean-A:beta=B,...,euclidean-N:beta=B,...` (codebook trained
# per method on the collection) and experiments/plot_beta.py: RUN/beta_sweep.{csv,png}, RUN/report.md.
# Other options (--simplify, --words, --threads, ...) go to canonform retrieve.
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,8p' "$0"; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cf=${CANONFORM:-$here/../build/apps/canonform}
dataset=$1; run=$2; shift 2
betas_a="2.5 5 10 15 20 40"
betas_n="30 65 130 200 300 600"
while [ $# -gt 0 ]; do
  case "$1" in
    --betas-a) betas_a=$2; shift 2 ;;
    --betas-n) betas_n=$2; shift 2 ;;
    *) break ;;
  esac
done
methods=""
for b in $betas_a; do methods="$methods,euclidean-A:beta=$b"; done
for b in $betas_n; do methods="$methods,euclidean-N:beta=$b"; done
methods=${methods#,}
[ -n "$methods" ] || { echo "beta_sweep.sh: no beta values" >&2; exit 2; }
start=$(date +%s)
"$cf" retrieve --dataset "$dataset" --out "$run" --method "$methods" "$@" > "$run.retrieve.log"
/usr/bin/python3 "$here/plot_beta.py" "$run" "$(basename "$dataset"): mean of NN, 1-tier, 2-tier, E, DCG"
echo "beta_sweep.sh: $(( $(date +%s) - start )) s; report $run/report.md, plot $run/beta_sweep.png"
