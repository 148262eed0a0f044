# SPDX-License-Identifier: GPL-3.0-or-later
"""Turns the benchmark's JSON lines into a Markdown table and a log-log plot.

usage: report.py RAW.jsonl OUT.md PLOT.png [--auto-from N]
(bench/run_bench.sh: bench/results/canonical_form.md, and the docs' picture
docs/images/bench_canonical_form.png: it is drawn there, where the pages take it, and nowhere else)
With --auto-from, an "auto" group per variant is added: the direct rows below N vertices and the
multigrid rows from N on (what SMACOF's default solver choice does).
Rows are grouped by variant and requested SMACOF solver (direct, multigrid, auto). Ratios are
against the smallest mesh of the same group, so linear growth shows as time ratio ~ vertex
ratio; the growth exponent is the least-squares slope of log time against log vertices.
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
out_md = sys.argv[2]
png = sys.argv[3]
auto_from = int(sys.argv[5]) if len(sys.argv) > 5 and sys.argv[4] == "--auto-from" else None
for r in rows:
    r.setdefault("requested_solver", "auto")
    r["group"] = f"{r['variant']} {r['requested_solver']}"
if auto_from:
    for r in list(rows):
        if (r["requested_solver"] == "direct" and r["vertices"] < auto_from) or (
                r["requested_solver"] == "multigrid" and r["vertices"] >= auto_from):
            a = dict(r)
            a["requested_solver"] = "auto"
            a["group"] = f"{r['variant']} auto"
            rows.append(a)


def slope(group):
    xs = [math.log(r["vertices"]) for r in group]
    ys = [math.log(r["median_s"]) for r in group]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


groups = {}
for name in sorted({r["group"] for r in rows}):
    group = sorted((r for r in rows if r["group"] == name), key=lambda r: r["vertices"])
    base = group[0]
    for r in group:
        r["vertex_ratio"] = r["vertices"] / base["vertices"]
        r["time_ratio"] = r["median_s"] / base["median_s"]
        r["us_per_vertex"] = 1e6 * r["median_s"] / r["vertices"]
        r["algorithm_mib"] = r["peak_mib"] - r["rss_loaded_mib"]
    groups[name] = group
rows.sort(key=lambda r: (r["group"], r["vertices"]))
with open(out_md, "w") as f:
    f.write("| variant | solver (used) | vertices | feature points | iterations | median s (runs) | us / vertex "
            "| vertices x | time x | peak MiB (algorithm) |\n|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        f.write(f"| {r['variant']} | {r['requested_solver']} ({r['solver']}) | {r['vertices']} "
                f"| {r['feature_points']} | {r['iterations']} "
                f"| {r['median_s']:.3f} ({r['repeats']}) | {r['us_per_vertex']:.1f} | {r['vertex_ratio']:.1f} "
                f"| {r['time_ratio']:.1f} | {r['peak_mib']:.0f} ({r['algorithm_mib']:.0f}) |\n")
    f.write("\n| variant, solver | growth exponent (log-log slope, all sizes) | from 10k up |\n|---|---|---|\n")
    for name, group in groups.items():
        upper = [r for r in group if r["vertices"] >= 9000]
        f.write(f"| {name} | {slope(group):.2f} | {slope(upper) if len(upper) > 1 else float('nan'):.2f} |\n")
    f.write("\n| variant | vertices | direct s | multigrid s | multigrid / direct |\n|---|---|---|---|---|\n")
    for variant in ("N", "A"):
        d = {r["vertices"]: r for r in groups.get(f"{variant} direct", [])}
        m = {r["vertices"]: r for r in groups.get(f"{variant} multigrid", [])}
        for n in sorted(set(d) & set(m)):
            f.write(f"| {variant} | {n} | {d[n]['median_s']:.3f} | {m[n]['median_s']:.3f} "
                    f"| {m[n]['median_s'] / d[n]['median_s']:.2f} |\n")
fig, ax = plt.subplots(figsize=(6, 4.2))
for (name, group), marker in zip(((k, v) for k, v in groups.items() if "auto" not in k), "os^v<>"):
    ax.loglog([r["vertices"] for r in group], [r["median_s"] for r in group], marker=marker, label=name)
if rows:
    n0 = min(r["vertices"] for r in rows)
    t0 = min(r["median_s"] for r in rows if r["vertices"] == n0)
    xs = sorted({r["vertices"] for r in rows})
    ax.loglog(xs, [t0 * x / n0 for x in xs], "k--", lw=0.8, label="linear in N")
ax.axhline(0.3, color="grey", lw=0.6, ls=":")
ax.set_xlabel("vertices")
ax.set_ylabel("median seconds (one core)")
ax.set_title("Euclidean canonical form: time against mesh size")
ax.legend(fontsize=8)
ax.grid(True, which="both", lw=0.3)
fig.tight_layout()
fig.savefig(png, dpi=110)
print(open(out_md).read())
