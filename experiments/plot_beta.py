# SPDX-License-Identifier: GPL-3.0-or-later
"""The paper's Fig. 6: mean of the five retrieval measures against beta, for both variants.

usage: /usr/bin/python3 experiments/plot_beta.py RUN_DIR [TITLE]
Reads RUN_DIR/*/metrics.json of a `canonform retrieve` run whose methods were
euclidean-A:beta=B and euclidean-N:beta=B (see experiments/beta_sweep.sh); writes
RUN_DIR/beta_sweep.csv (variant, beta, the five micro measures, their mean, pose consistency)
and RUN_DIR/beta_sweep.png (one panel per variant, like Fig. 6 (a) and (b)).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_metrics import MEASURES, method_metrics  # noqa: E402

run = sys.argv[1]
title = sys.argv[2] if len(sys.argv) > 2 else os.path.basename(os.path.normpath(run))
rows = []
for d, j in method_metrics(run):
    base = j.get("base", "")
    if base not in ("euclidean-A", "euclidean-N"):
        continue
    micro = j["micro"]
    mean = sum(micro[m] for m in MEASURES) / len(MEASURES)
    rows.append({"variant": base[-1], "beta": float(j["beta"]), **{m: micro[m] for m in MEASURES},
                 "mean": mean, "pose_consistency": j.get("pose_consistency", -1), "method": d})
if not rows:
    sys.exit(f"plot_beta.py: no euclidean-A/N METHOD/metrics.json in {run}")
rows.sort(key=lambda r: (r["variant"], r["beta"]))
out_csv = os.path.join(run, "beta_sweep.csv")
with open(out_csv + ".tmp", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["variant", "beta", *MEASURES, "mean", "pose_consistency", "method"])
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.4f}" if isinstance(v, float) and k != "beta" else v) for k, v in r.items()})
os.replace(out_csv + ".tmp", out_csv)

variants = [v for v in ("A", "N") if any(r["variant"] == v for r in rows)]
fig, axes = plt.subplots(1, len(variants), figsize=(4.6 * len(variants), 3.6), squeeze=False)
names = {"A": "(a) additional random feature points (A)", "N": "(b) normalised weightings (N)"}
for ax, v in zip(axes[0], variants):
    rs = [r for r in rows if r["variant"] == v]
    b = [r["beta"] for r in rs]
    ax.plot(b, [r["mean"] for r in rs], marker="o", color="k", label="mean of the five")
    for m, style in zip(MEASURES, [":", "--", "-.", (0, (1, 3)), (0, (5, 2, 1, 2))]):
        ax.plot(b, [r[m] for r in rs], lw=0.8, ls=style, alpha=0.7, label=m.replace("_", " "))
    best = max(rs, key=lambda r: r["mean"])
    ax.axvline(best["beta"], color="r", lw=0.6)
    ax.axvline(10 if v == "A" else 130, color="grey", lw=0.8, ls="--", label="paper's beta")
    pc = [(r["beta"], r["pose_consistency"]) for r in rs if r["pose_consistency"] >= 0]
    if pc:  # pose left over (lower = more pose removed), on its own axis
        ax2 = ax.twinx()
        ax2.plot([b for b, _ in pc], [c for _, c in pc], color="tab:purple", marker="s", ms=3, lw=1,
                 label="pose consistency (right)")
        ax2.set_ylabel("pose consistency (lower = less pose)", color="tab:purple", fontsize=8)
        ax2.tick_params(axis="y", labelcolor="tab:purple", labelsize=7)
        if v == variants[-1]:
            ax2.legend(fontsize=7, loc="lower right")
    ax.set_xscale("log")
    ax.set_xlabel("beta")
    ax.set_ylabel("retrieval measure (micro)")
    ax.set_title(f"{names[v]}\nbest mean {best['mean']:.3f} at beta {best['beta']:g}", fontsize=9)
    ax.grid(True, lw=0.3)
axes[0][0].legend(fontsize=7)
fig.suptitle(title, fontsize=10)
fig.tight_layout()
out = os.path.join(run, "beta_sweep.png")
fig.savefig(out + ".tmp.png", dpi=100)
os.replace(out + ".tmp.png", out)
for r in rows:
    print(f"{r['variant']} beta={r['beta']:g}: mean {r['mean']:.3f} "
          + " ".join(f"{m}={r[m]:.3f}" for m in MEASURES) + f" pose={r['pose_consistency']:.3f}")
print(out)
