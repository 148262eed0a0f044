#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot of bench/run_bench_acceleration.sh: Guttman steps and SMACOF seconds per mesh against the
vertex count (procedural figures), one line per acceleration.
   plot_acceleration.py acceleration.csv acceleration.png"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["set"].startswith("procedural-") and r["variant"] == "N"]
methods = list(dict.fromkeys(r["acceleration"] for r in rows))
fig, ax = plt.subplots(1, 2, figsize=(10, 4))
for m in methods:
    rs = sorted((r for r in rows if r["acceleration"] == m), key=lambda r: int(r["vertices"]))
    n = [int(r["vertices"]) for r in rs]
    ax[0].plot(n, [float(r["median_steps"]) for r in rs], "o-", label=m)
    ax[1].plot(n, [float(r["smacof_seconds"]) / int(r["meshes"]) for r in rs], "o-", label=m)
for a, t in zip(ax, ["Guttman steps (median over poses)", "SMACOF seconds per mesh"]):
    a.set_xscale("log")
    a.set_xlabel("vertices")
    a.set_title(t)
    a.grid(True, which="both", alpha=0.3)
ax[1].set_yscale("log")
ax[0].legend()
fig.suptitle("Euclidean canonical form (N), SMACOF accelerations, one core (shared machine)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=100)
