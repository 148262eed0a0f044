"""Turns the benchmark's JSON lines into a CSV, a Markdown table and a log-log plot.

usage: report.py RAW.jsonl OUT_PREFIX   (writes OUT_PREFIX.csv, .md, .png)
Ratios are against the smallest mesh of the same variant, so linear growth shows as
time ratio ~ vertex ratio.
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
prefix = sys.argv[2]
for variant in {r["variant"] for r in rows}:
    group = sorted((r for r in rows if r["variant"] == variant), key=lambda r: r["vertices"])
    base = group[0]
    for r in group:
        r["vertex_ratio"] = r["vertices"] / base["vertices"]
        r["time_ratio"] = r["median_s"] / base["median_s"]
        r["us_per_vertex"] = 1e6 * r["median_s"] / r["vertices"]
        r["algorithm_mib"] = r["peak_mib"] - r["rss_loaded_mib"]
rows.sort(key=lambda r: (r["variant"], r["vertices"]))
fields = ["variant", "vertices", "feature_points", "iterations", "repeats", "median_s", "min_s", "max_s",
          "us_per_vertex", "vertex_ratio", "time_ratio", "peak_mib", "algorithm_mib"]
with open(prefix + ".csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
    w.writeheader()
    w.writerows(rows)
with open(prefix + ".md", "w") as f:
    f.write("| variant | vertices | feature points | iterations | median s (runs) | us / vertex "
            "| vertices x | time x | peak MiB (algorithm) |\n|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        f.write(f"| {r['variant']} | {r['vertices']} | {r['feature_points']} | {r['iterations']} "
                f"| {r['median_s']:.3f} ({r['repeats']}) | {r['us_per_vertex']:.1f} | {r['vertex_ratio']:.1f} "
                f"| {r['time_ratio']:.1f} | {r['peak_mib']:.0f} ({r['algorithm_mib']:.0f}) |\n")
fig, ax = plt.subplots(figsize=(6, 4.2))
for variant, marker in (("N", "o"), ("A", "s")):
    g = [r for r in rows if r["variant"] == variant]
    if g:
        ax.loglog([r["vertices"] for r in g], [r["median_s"] for r in g], marker=marker, label=f"variant {variant}")
if rows:
    n0 = min(r["vertices"] for r in rows)
    t0 = min(r["median_s"] for r in rows if r["vertices"] == n0)
    xs = sorted({r["vertices"] for r in rows})
    ax.loglog(xs, [t0 * x / n0 for x in xs], "k--", lw=0.8, label="linear in N")
ax.axhline(0.3, color="grey", lw=0.6, ls=":")
ax.set_xlabel("vertices")
ax.set_ylabel("median seconds (one core)")
ax.set_title("Euclidean canonical form: time against mesh size")
ax.legend()
ax.grid(True, which="both", lw=0.3)
fig.tight_layout()
fig.savefig(prefix + ".png", dpi=110)
print(open(prefix + ".md").read())
