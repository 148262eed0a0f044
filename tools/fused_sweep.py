"""Weight sweep of a fused method from a finished `canonform retrieve` run (no recomputation).

usage: /usr/bin/python3 tools/fused_sweep.py CANONFORM RUN_DIR METHOD_A METHOD_B [W ...]
For each weight W of METHOD_B (default 0, 0.1, ..., 1; METHOD_A gets 1 - W) it forms
(1 - W) * D_A / median(D_A) + W * D_B / median(D_B) from RUN_DIR/METHOD/distances.bin (medians of
the off-diagonal entries, as fused_distances.h), scores it with `CANONFORM evaluate --json`, and
prints one CSV row per weight (w_b, nn, first_tier, second_tier, e_measure, dcg, mean) and
writes them to RUN_DIR/fused_sweep_A+B.csv.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

cf, run, a, b = sys.argv[1:5]
weights = [float(w) for w in sys.argv[5:]] or [k / 10 for k in range(11)]


def load(method):
    d = os.path.join(run, method)
    names = [line.split(",")[0] for line in open(os.path.join(d, "models.csv")).read().splitlines()[1:] if line]
    D = np.fromfile(os.path.join(d, "distances.bin"), dtype="<f4").reshape(len(names), len(names))
    return names, D


def median_off(D):
    return float(np.median(D[~np.eye(D.shape[0], dtype=bool)])) or 1.0


na, Da = load(a)
nb, Db = load(b)
common = [n for n in na if n in set(nb)]
ia = [na.index(n) for n in common]
ib = [nb.index(n) for n in common]
Da = Da[np.ix_(ia, ia)].astype(np.float64)
Db = Db[np.ix_(ib, ib)].astype(np.float64)
Da /= median_off(Da)
Db /= median_off(Db)
classes = dict(line.split(",")[:2] for line in open(os.path.join(run, a, "models.csv")).read().splitlines()[1:] if line)
rows = []
with tempfile.TemporaryDirectory() as tmp:
    labels = os.path.join(tmp, "labels.csv")
    with open(labels, "w") as f:
        f.write("path,class\n" + "".join(f"{n},{classes[n]}\n" for n in common))
    for w in weights:
        F = ((1 - w) * Da + w * Db).astype("<f4")
        mat = os.path.join(tmp, "fused.bin")
        F.tofile(mat)
        j = json.loads(subprocess.run([cf, "evaluate", mat, "--labels", labels, "--json"], check=True,
                                      capture_output=True, text=True).stdout)["micro"]
        m = [j[k] for k in ("nn", "first_tier", "second_tier", "e_measure", "dcg")]
        rows.append([w] + m + [sum(m) / 5])
out = os.path.join(run, f"fused_sweep_{a}+{b}.csv")
with open(out, "w") as f:
    f.write("w_" + b + ",nn,first_tier,second_tier,e_measure,dcg,mean\n")
    for r in rows:
        f.write(",".join("%.3f" % x for x in r) + "\n")
print(open(out).read(), end="")
