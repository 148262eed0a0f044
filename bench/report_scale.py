# SPDX-License-Identifier: GPL-3.0-or-later
"""Prints bench/run_bench_scale.sh's JSON lines as a Markdown table (the docs' table is generated from
the JSON lines themselves).

usage: report_scale.py RAW.jsonl
One row per binary and mesh size: medians over the runs of wall and CPU (user + system) seconds,
of every stage's seconds (read = reading and validating the file; conformal factor; setup =
edges, feature points, SMACOF's pairs, V and its multigrid hierarchy; SMACOF iterations; write;
"other" = wall - the stages: process start, scaling, exit), peak RSS and minor page faults, and
the final stress (relative to the baseline's on the same mesh, if there is one).
"""
import json
import statistics
import sys

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
groups = {}
for r in rows:
    r["cpu_s"] = r["user_s"] + r["system_s"]
    # Builds before write_seconds existed: the write is what total_seconds adds to read and the method.
    r.setdefault("write_seconds", r["total_seconds"] - r["read_seconds"] - r["seconds"])
    r["other_s"] = r["wall_s"] - (r["read_seconds"] + r["conformal_factor_seconds"] + r["setup_seconds"]
                                  + r["smacof_seconds"] + r["write_seconds"])
    groups.setdefault((r["vertices"], r["binary"]), []).append(r)

cols = [("wall_s", "wall s"), ("cpu_s", "CPU s"), ("user_s", "user s"), ("system_s", "system s"),
        ("read_seconds", "read s"), ("conformal_factor_seconds", "conformal factor s"),
        ("setup_seconds", "setup s"), ("smacof_seconds", "SMACOF s"), ("write_seconds", "write s"),
        ("other_s", "other s")]
out = []
for (n, binary), g in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1] != "baseline")):
    row = {"vertices": n, "binary": binary, "runs": len(g)}
    for key, _ in cols:
        row[key] = statistics.median(r[key] for r in g)
    row["peak_rss_mib"] = statistics.median(r["peak_rss_kib"] for r in g) / 1024
    row["minor_faults"] = statistics.median(r["minor_faults"] for r in g)
    row["iterations"] = g[0]["iterations"]
    row["final_stress"] = g[0]["final_stress"]
    base = groups.get((n, "baseline"))
    row["stress_vs_baseline"] = g[0]["final_stress"] / base[0]["final_stress"] if base else None
    row["wall_x"] = (statistics.median(r["wall_s"] for r in base) / row["wall_s"]) if base else None
    out.append(row)

head = ["vertices", "binary", "runs"] + [c[1] for c in cols] + ["peak RSS MiB", "minor faults", "iterations",
                                                                "final stress", "stress / baseline", "wall x"]
lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
for r in out:
    cells = [f"{r['vertices']}", r["binary"], f"{r['runs']}"] + [f"{r[k]:.2f}" for k, _ in cols]
    cells += [f"{r['peak_rss_mib']:.0f}", f"{r['minor_faults']:.0f}", f"{r['iterations']}", f"{r['final_stress']:.4f}",
              f"{r['stress_vs_baseline']:.6f}" if r["stress_vs_baseline"] else "-",
              f"{r['wall_x']:.2f}" if r["wall_x"] else "-"]
    lines.append("| " + " | ".join(cells) + " |")
print("\n".join(lines))
