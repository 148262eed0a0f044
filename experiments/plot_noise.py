# SPDX-License-Identifier: GPL-3.0-or-later
"""The paper's Table 5 (retrieval under vertex noise) as a curve: measures against noise sigma.

usage: /usr/bin/python3 experiments/plot_noise.py OUT_PREFIX SIGMA=RUN_DIR [SIGMA=RUN_DIR ...]
Each RUN_DIR is a `canonform retrieve --noise SIGMA` run (same collection and methods; see
experiments/noise_sweep.sh). Writes OUT_PREFIX.csv (sigma, method, the five micro measures, their mean)
and OUT_PREFIX.png (nearest neighbour, first tier and the mean of the five against sigma, one
line per method).
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
# One fixed look per method (colour by family, line style and marker per member) so that six
# methods stay apart where their lines cross; unknown methods (e.g. fused) get the default cycle.
STYLE = {
    "none": ("0.45", ":", "s"),
    "euclidean-A": ("tab:blue", "-", "o"),
    "euclidean-N": ("tab:cyan", "-", "^"),
    "geodesic-ls": ("tab:red", "--", "D"),
    "geodesic-classical": ("tab:orange", "--", "v"),
    "geodesic-fast": ("tab:brown", "--", "P"),
}
order = list(STYLE)
methods = sorted({r[1] for r in rows}, key=lambda m: (order.index(m) if m in order else len(order), m))
panels = ((2, "nearest neighbour"), (3, "first tier"), (7, "mean of the five measures"))
fig, axes = plt.subplots(1, len(panels), figsize=(13, 4.4))
for ax, (col, name) in zip(axes, panels):
    for m in methods:
        pts = [(r[0], r[col]) for r in rows if r[1] == m]
        colour, line, marker = STYLE.get(m, (None, "-", "o"))
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour, linestyle=line,
                marker=marker, markersize=6, linewidth=1.6, label=m)
    ax.set_xticks(sorted({r[0] for r in rows}))
    ax.set_xlabel("noise sigma (x mean edge length)")
    ax.set_title(name)
    ax.grid(alpha=0.3)
handles, labels = axes[0].get_legend_handles_labels()
fig.legend(handles, labels, loc="lower center", ncol=min(len(methods), 6), frameon=False)
fig.suptitle("retrieval against vertex noise (one run per sigma)")
fig.tight_layout(rect=(0, 0.08, 1, 1))
fig.savefig(out + ".png", dpi=110)
print("wrote", out + ".csv", out + ".png")
