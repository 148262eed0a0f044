# SPDX-License-Identifier: GPL-3.0-or-later
"""Precision-recall curves of every method of a `canonform retrieve` run on one plot.

usage: /usr/bin/python3 tools/plot_pr.py RUN_DIR [TITLE]   (writes RUN_DIR/pr.png from RUN_DIR/*/pr.csv)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

run = sys.argv[1]
methods = sorted(d for d in os.listdir(run) if os.path.isfile(os.path.join(run, d, "pr.csv")))
if not methods:
    sys.exit(f"plot_pr.py: no METHOD/pr.csv in {run}")
fig, ax = plt.subplots(figsize=(5.6, 4.2))
for m in methods:
    with open(os.path.join(run, m, "pr.csv")) as f:
        rows = list(csv.DictReader(f))
    ax.plot([float(r["recall"]) for r in rows], [float(r["precision"]) for r in rows], marker="o", ms=3, label=m)
ax.set_xlabel("recall")
ax.set_ylabel("precision")
ax.set_xlim(0, 1.02)
ax.set_ylim(0, 1.02)
ax.grid(True, lw=0.3)
ax.legend()
ax.set_title(sys.argv[2] if len(sys.argv) > 2 else os.path.basename(os.path.normpath(run)), fontsize=9)
fig.tight_layout()
out = os.path.join(run, "pr.png")
tmp = out + ".tmp.png"
fig.savefig(tmp, dpi=110)
os.replace(tmp, out)
print(out)
