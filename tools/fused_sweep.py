# SPDX-License-Identifier: GPL-3.0-or-later
"""Weight sweep of a fused method from a finished `canonform retrieve` run (no recomputation).

usage: /usr/bin/python3 tools/fused_sweep.py CANONFORM RUN_DIR METHOD_A METHOD_B [W ...] [--rule zscore|median]
For each weight W of METHOD_B (default 0, 0.1, ..., 1; METHOD_A gets 1 - W) it forms the fused
matrix of RUN_DIR/METHOD/distances.bin as retrieval/fused_distances.h does:
  zscore (default, `fused:`): each member's distances z-normalised per query (row, off-diagonal
    entries), (1 - W) * Z_A + W * Z_B, symmetrised ((F + F^T) / 2);
  median (`fused-median:`): (1 - W) * D_A / median(D_A) + W * D_B / median(D_B), medians of the
    off-diagonal entries;
scores it with `CANONFORM evaluate --json`, and prints one CSV row per weight (w_b, nn,
first_tier, second_tier, e_measure, dcg, mean), preceded by the raw members' rows ("A" and "B":
their own distance matrices, as `retrieve` scores them), and writes them to
RUN_DIR/fused_sweep[_median]_A+B.csv. Under zscore, W = 0 and W = 1 are one member re-ranked by
the rule (its z-normalised, symmetrised matrix), not the member itself.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from run_matrices import load_method

args = sys.argv[1:]
rule = "zscore"
if "--rule" in args:
    i = args.index("--rule")
    rule = args[i + 1]
    del args[i:i + 2]
if rule not in ("zscore", "median") or len(args) < 4:
    sys.exit(__doc__)
cf, run, a, b = args[:4]
weights = [float(w) for w in args[4:]] or [k / 10 for k in range(11)]


def load(method):
    names, _, D = load_method(os.path.join(run, method))
    return names, D


def off(n):
    return ~np.eye(n, dtype=bool)


def median_normalised(D):
    return D / (float(np.median(D[off(D.shape[0])])) or 1.0)


def row_zscores(D):
    n = D.shape[0]
    X = np.where(off(n), D, np.nan)
    mean = np.nanmean(X, axis=1, keepdims=True)
    sd = np.nanstd(X, axis=1, keepdims=True)
    Z = (D - mean) / np.where(sd > 0, sd, 1.0)
    np.fill_diagonal(Z, 0)
    return Z


def fused(w):
    if rule == "median":
        return (1 - w) * Na + w * Nb
    F = (1 - w) * Na + w * Nb
    F = 0.5 * (F + F.T)
    F -= F[off(F.shape[0])].min()
    np.fill_diagonal(F, 0)
    return F


na, Da = load(a)
nb, Db = load(b)
common = [n for n in na if n in set(nb)]
ia = [na.index(n) for n in common]
ib = [nb.index(n) for n in common]
Da = Da[np.ix_(ia, ia)].astype(np.float64)
Db = Db[np.ix_(ib, ib)].astype(np.float64)
normalise = median_normalised if rule == "median" else row_zscores
Na, Nb = normalise(Da), normalise(Db)
classes = load_method(os.path.join(run, a))[1]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    labels = os.path.join(tmp, "labels.csv")
    with open(labels, "w") as f:
        f.write("path,class\n" + "".join(f"{n},{classes[n]}\n" for n in common))

    def score(F):
        mat = os.path.join(tmp, "fused.bin")
        F.astype("<f4").tofile(mat)
        j = json.loads(subprocess.run([cf, "evaluate", mat, "--labels", labels, "--json"], check=True,
                                      capture_output=True, text=True).stdout)["micro"]
        m = [j[k] for k in ("nn", "first_tier", "second_tier", "e_measure", "dcg")]
        return m + [sum(m) / 5]

    rows.append(["A"] + score(Da))
    rows.append(["B"] + score(Db))
    for w in weights:
        rows.append(["%.3f" % w] + score(fused(w)))
out = os.path.join(run, f"fused_sweep{'_median' if rule == 'median' else ''}_{a}+{b}.csv")
with open(out, "w") as f:
    f.write("w_" + b + ",nn,first_tier,second_tier,e_measure,dcg,mean\n")
    for r in rows:
        f.write(",".join([r[0]] + ["%.3f" % x for x in r[1:]]) + "\n")
print(open(out).read(), end="")
