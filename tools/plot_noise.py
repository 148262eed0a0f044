"""The paper's Table 5 (retrieval under vertex noise) as a curve: measures against noise sigma.

usage: /usr/bin/python3 tools/plot_noise.py OUT_PREFIX SIGMA=RUN_DIR [SIGMA=RUN_DIR ...]
Each RUN_DIR is a `canonform retrieve --noise SIGMA` run (same collection and methods; see
tools/noise_sweep.sh). Writes OUT_PREFIX.csv (sigma, method, the five micro measures, their mean)
and OUT_PREFIX.png (first tier and the mean of the five against sigma, one line per method).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_metrics import MEASURES, method_metrics  # noqa: E402

out = sys.argv[1]
rows = []
for arg in sys.argv[2:]:
    sigma, run = arg.split("=", 1)
    for d, j in method_metrics(run):
        if not j.get("micro"):
            continue
        m = [j["micro"][k] for k in MEASURES]
        rows.append([float(sigma), j["method"]] + m + [sum(m) / len(m)])
rows.sort()
with open(out + ".csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["sigma", "method"] + MEASURES + ["mean"])
    for r in rows:
        w.writerow([r[0], r[1]] + ["%.3f" % x for x in r[2:]])
methods = sorted({r[1] for r in rows})
fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for ax, col, name in ((axes[0], 3, "first tier"), (axes[1], 7, "mean of the five measures")):
    for m in methods:
        pts = [(r[0], r[col]) for r in rows if r[1] == m]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=m)
    ax.set_xlabel("noise sigma (fraction of the mean edge length)")
    ax.set_ylabel(name)
    ax.grid(alpha=0.3)
axes[0].legend()
fig.suptitle(os.path.basename(out))
fig.tight_layout()
fig.savefig(out + ".png", dpi=110)
print("wrote", out + ".csv", out + ".png")
