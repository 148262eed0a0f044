# SPDX-License-Identifier: GPL-3.0-or-later
"""Table 1 / Fig. 7 report: a Markdown table (seconds and peak MiB per method and size, and the
speed-up of the Euclidean form over geodesic least squares) and a log-log plot of time against
vertices. usage: report_table1.py RAW.jsonl OUT.md PLOT.png (bench/run_table1.sh:
bench/results/table1.md and the docs' picture docs/images/bench_table1.png, drawn only there)"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
out_md, png = sys.argv[2], sys.argv[3]
methods = ["euclidean-A", "euclidean-N", "geodesic-fast", "geodesic-classical", "geodesic-ls"]
labels = {"euclidean-A": "Euclidean A", "euclidean-N": "Euclidean N", "geodesic-fast": "geodesic F",
          "geodesic-classical": "geodesic C", "geodesic-ls": "geodesic LS"}
by = {(r["method"], r["vertices"]): r for r in rows}
sizes = sorted({r["vertices"] for r in rows})
with open(out_md, "w") as f:
    f.write("| vertices | " + " | ".join(labels[m] + " s (MiB)" for m in methods)
            + " | LS / Euclidean N | LS / Euclidean A |\n")
    f.write("|---" * (len(methods) + 3) + "|\n")
    for n in sizes:
        cells = []
        for m in methods:
            r = by.get((m, n))
            cells.append(f"{r['median_s']:.3g} ({r['peak_mib']:.0f})" if r else "-")
        ls, en, ea = by.get(("geodesic-ls", n)), by.get(("euclidean-N", n)), by.get(("euclidean-A", n))
        rn = f"{ls['median_s'] / en['median_s']:.0f}x" if ls and en else "-"
        ra = f"{ls['median_s'] / ea['median_s']:.0f}x" if ls and ea else "-"
        f.write(f"| {n} | " + " | ".join(cells) + f" | {rn} | {ra} |\n")
fig, ax = plt.subplots(figsize=(6.4, 4.4))
for m, style in zip(methods, ["s-", "o-", "v--", "^--", "D--"]):
    pts = sorted((r["vertices"], r["median_s"]) for r in rows if r["method"] == m)
    if pts:
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, label=labels[m])
ax.set_xlabel("vertices")
ax.set_ylabel("median seconds (one core)")
ax.set_title("Canonical forms: Euclidean (Pickup et al.) vs geodesic (Elad-Kimmel)")
ax.grid(True, which="both", lw=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(png, dpi=110)
print(open(out_md).read())
