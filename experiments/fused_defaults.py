# SPDX-License-Identifier: GPL-3.0-or-later
"""The fused method's default, chosen over several collections at once (no recomputation).

usage: /usr/bin/python3 experiments/fused_defaults.py CANONFORM --collection NAME RUN [RUN ...]
           [--collection NAME RUN ...] [--rules RULE,...] [--weights W ...] [--json FILE]
           [--command TEXT] [--conditions TEXT] [--top N] [--keep RULE:W ...]
Each RUN is a finished `canonform retrieve` run (one codebook seed) with the members `none` and
`euclidean-N` (RUN/none/distances.bin, RUN/euclidean-N/distances.bin). For every rule of
experiments/fused_rules.py (default: row-z, rrf60, rank-sum, distinct5, global-median) and every weight W
of euclidean-N (default 0.1 ... 0.9; none gets 1 - W), the fused matrix of every run is scored with
`CANONFORM evaluate --json`. A run's margin is the fused first tier minus the better member's first
tier in that run; a collection's margin is the mean over its runs (seeds), with the smallest and
largest; a candidate's criterion is the worst collection margin. Prints, sorted by the criterion,
one row per candidate: the margin per collection (mean, and min..max over seeds) and the
criterion; the members alone first (their first tier per collection). --json FILE writes the same
as a results record (bench/results/retrieval/*.json: title, command, conditions, columns, rows):
the members, the best N candidates (--top, default all) and the candidates named by --keep
(e.g. row-z:0.9, a previous default).
The candidates with no constant of their own are the equal-weight ones (W = 0.5) of row-z and
rank-sum; rrf60 has RRF's customary k = 60, distinct5 its k = 5.
"""
import os
import sys
import tempfile

import numpy as np

from fused_rules import MEASURES, RULES, evaluate, member_pair

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "docs"))
from record_run import dump  # noqa: E402

DEFAULT_RULES = ["row-z", "rrf60", "rank-sum", "distinct5", "global-median"]
DEFAULT_WEIGHTS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]


def parse(argv):
    if not argv or argv[0].startswith("--"):
        sys.exit(__doc__)
    opts = {"cf": argv[0], "collections": [], "rules": DEFAULT_RULES, "weights": DEFAULT_WEIGHTS,
            "json": None, "command": "", "conditions": "", "top": None, "keep": []}
    i = 1
    while i < len(argv):
        a = argv[i]
        if a == "--collection":
            if i + 1 >= len(argv):
                sys.exit("--collection needs a name and at least one run")
            name, runs = argv[i + 1], []
            i += 2
            while i < len(argv) and not argv[i].startswith("--"):
                runs.append(argv[i]); i += 1
            if not runs:
                sys.exit("--collection %s: no run folders" % name)
            opts["collections"].append((name, runs))
        elif a == "--rules":
            opts["rules"] = argv[i + 1].split(","); i += 2
        elif a == "--weights":
            i += 1
            opts["weights"] = []
            while i < len(argv) and not argv[i].startswith("--"):
                opts["weights"].append(float(argv[i])); i += 1
        elif a in ("--json", "--command", "--conditions"):
            opts[a[2:]] = argv[i + 1]; i += 2
        elif a == "--top":
            opts["top"] = int(argv[i + 1]); i += 2
        elif a == "--keep":
            i += 1
            while i < len(argv) and not argv[i].startswith("--"):
                rule, _, w = argv[i].partition(":")
                opts["keep"].append((rule, float(w))); i += 1
        else:
            sys.exit("unknown argument %s\n%s" % (a, __doc__))
    if not opts["collections"]:
        sys.exit("no --collection given\n" + __doc__)
    known = {r[0]: r for r in RULES}
    for r in opts["rules"]:
        if r not in known:
            sys.exit("unknown rule %s (rules: %s)" % (r, ", ".join(known)))
    opts["rules"] = [known[r] for r in opts["rules"]]
    return opts


def main():
    o = parse(sys.argv[1:])
    with tempfile.TemporaryDirectory() as tmp:
        def score(F, labels):
            return evaluate(o["cf"], F, labels, tmp, "fused_defaults.py")

        data = {}  # collection -> [(Da, Db, labels)]
        for c, (name, runs) in enumerate(o["collections"]):
            data[name] = []
            for k, run in enumerate(runs):
                labels = os.path.join(tmp, "labels%d_%d.csv" % (c, k))
                data[name].append(member_pair(run, "none", "euclidean-N", labels) + (labels,))
        names = [n for n, _ in o["collections"]]
        alone = {n: [(score(Da, lab), score(Db, lab)) for Da, Db, lab in data[n]] for n in names}
        best = {n: [max(a["first_tier"], b["first_tier"]) for a, b in alone[n]] for n in names}
        rows = []
        for member, idx in (("none", 0), ("euclidean-N", 1)):
            row = {"rule": member + " alone", "weight": None}
            for n in names:
                ft = [pair[idx]["first_tier"] for pair in alone[n]]
                m = [f - b for f, b in zip(ft, best[n])]
                row[n] = {"first_tier": float(np.mean(ft)), "margin": float(np.mean(m)), "min": min(m), "max": max(m)}
            row["worst"] = min(row[n]["margin"] for n in names)
            rows.append(row)
        for rule, title, fuse in o["rules"]:
            for w in o["weights"]:
                row = {"rule": rule, "title": title, "weight": w}
                for n in names:
                    s = [score(fuse(Da, Db, w), lab) for Da, Db, lab in data[n]]
                    m = [x["first_tier"] - b for x, b in zip(s, best[n])]
                    row[n] = {"first_tier": float(np.mean([x["first_tier"] for x in s])), "margin": float(np.mean(m)),
                              "min": min(m), "max": max(m)}
                row["worst"] = min(row[n]["margin"] for n in names)
                rows.append(row)
                print("scored %s w=%g" % (rule, w), file=sys.stderr, flush=True)
    members, fused = rows[:2], sorted(rows[2:], key=lambda r: -r["worst"])
    seeds = "/".join(str(len(r)) for _, r in o["collections"])
    print("| rule | weight of euclidean-N | %s | worst |" % " | ".join(names))
    print("|---|---|" + "---|" * len(names) + "---|")
    for r in members:
        print("| %s | - | %s | %+.3f |" % (r["rule"], " | ".join("1-Tier %.3f (%+.3f)" % (r[n]["first_tier"], r[n]["margin"])
                                                                   for n in names), r["worst"]))
    for r in fused:
        print("| %s | %g | %s | %+.3f |" % (r["rule"], r["weight"], " | ".join(
            "%+.3f (%+.3f..%+.3f)" % (r[n]["margin"], r[n]["min"], r[n]["max"]) for n in names), r["worst"]))
    if o["json"]:
        columns = [{"key": "rule", "title": "rule"}, {"key": "weight", "title": "weight of euclidean-N"}]
        for n in names:
            columns.append({"key": n, "title": n + " margin", "digits": 3})
            columns.append({"key": n + "_spread", "title": n + " min..max over seeds"})
        columns.append({"key": "worst", "title": "worst margin", "best": "max", "digits": 3})
        out = []
        top = o["top"] if o["top"] is not None else len(fused)
        shown = [r for k, r in enumerate(fused)
                 if k < top or any(r["rule"] == rule and abs(r["weight"] - w) < 1e-9 for rule, w in o["keep"])]
        for r in members + shown:
            e = {"rule": r["rule"], "weight": "-" if r["weight"] is None else r["weight"], "worst": round(r["worst"], 4)}
            for n in names:
                e[n] = round(r[n]["margin"], 4)
                e[n + "_spread"] = "%+.3f..%+.3f" % (r[n]["min"], r[n]["max"])
            out.append(e)
        rec = {"title": "Fused rules and weights: first-tier margin over the better member, per collection "
                        "(mean over codebook seeds; runs per collection %s)" % seeds,
               "command": o["command"] or "experiments/fused_defaults.py " + " ".join(sys.argv[1:]),
               "conditions": o["conditions"], "columns": columns, "rows": out}
        with open(o["json"], "w") as f:
            f.write(dump(rec))


if __name__ == "__main__":
    main()
