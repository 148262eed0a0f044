# SPDX-License-Identifier: GPL-3.0-or-later
"""How sure is a difference between two retrieval set-ups? A paired comparison over the queries.

usage: /usr/bin/python3 experiments/paired_queries.py --a RUN [RUN ...] --b RUN [RUN ...] [--method M]
           [--resamples N] [--seed S] [--json]

Each RUN is a finished `canonform retrieve` folder (RUN/M/distances.csv, RUN/M/models.csv); the A
runs and the B runs are repeats of the two set-ups (for instance codebook seeds 0, 1, 2 of two SIFT
extractors) on the same collection. For every query (a model against all the others) the script
computes its NN (1 if its nearest other model is of its class) and its first tier (the share of
its class among its C - 1 nearest others, C the class size), averages each over the runs of a
set-up, and reports per measure: the mean of A and of B over the queries (the micro-averaged
measure of `canonform evaluate`), their difference B - A, and a 95% interval of that difference by
a paired bootstrap over the queries (N resamples of the query set with replacement, fixed seed; the
2.5th and 97.5th percentiles). The seed spread of one set-up says how much its codebook moves a
measure; this interval says how much the choice of queries does: a difference whose interval
holds 0 is not told apart from chance by this collection. Distance ties are broken by model index.
"""
import argparse
import csv
import json
import os
import random
import sys


def read_run(run, method):
    folder = os.path.join(run, method)
    with open(os.path.join(folder, "models.csv")) as f:
        labels = [row["class"] for row in csv.DictReader(f)]
    with open(os.path.join(folder, "distances.csv")) as f:
        D = [[float(x) for x in row] for row in csv.reader(f) if row]
    if len(D) != len(labels) or any(len(r) != len(labels) for r in D):
        sys.exit(f"paired_queries.py: {folder}: distances.csv is not {len(labels)} x {len(labels)} (models.csv)")
    return labels, D


def per_query(labels, D):
    """NN and first tier of each query."""
    n = len(labels)
    size = {}
    for c in labels:
        size[c] = size.get(c, 0) + 1
    nn, ft = [], []
    for i in range(n):
        order = sorted((j for j in range(n) if j != i), key=lambda j: (D[i][j], j))
        nn.append(1.0 if labels[order[0]] == labels[i] else 0.0)
        k = size[labels[i]] - 1
        ft.append(sum(labels[j] == labels[i] for j in order[:k]) / k if k > 0 else 0.0)
    return {"nn": nn, "first_tier": ft}


def setup(runs, method):
    labels, per = None, []
    for run in runs:
        lab, D = read_run(run, method)
        if labels is not None and lab != labels:
            sys.exit(f"paired_queries.py: {run}: not the same models as {runs[0]}")
        labels = lab
        per.append(per_query(lab, D))
    return labels, {m: [sum(p[m][q] for p in per) / len(per) for q in range(len(labels))] for m in per[0]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a", nargs="+", required=True)
    ap.add_argument("--b", nargs="+", required=True)
    ap.add_argument("--method", default="euclidean-N")
    ap.add_argument("--resamples", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    la, A = setup(a.a, a.method)
    lb, B = setup(a.b, a.method)
    if la != lb:
        sys.exit("paired_queries.py: the A and B runs do not hold the same models")
    n = len(la)
    rng = random.Random(a.seed)
    samples = [[rng.randrange(n) for _ in range(n)] for _ in range(a.resamples)]
    out = {"method": a.method, "queries": n, "runs_a": len(a.a), "runs_b": len(a.b), "resamples": a.resamples,
           "seed": a.seed, "measures": {}}
    for m in A:
        d = [B[m][q] - A[m][q] for q in range(n)]
        boot = sorted(sum(d[q] for q in s) / n for s in samples)
        lo, hi = boot[int(0.025 * (len(boot) - 1))], boot[int(0.975 * (len(boot) - 1))]
        out["measures"][m] = {"a": sum(A[m]) / n, "b": sum(B[m]) / n, "difference": sum(d) / n,
                              "interval": [lo, hi]}
    if a.json:
        print(json.dumps(out, indent=1))
        return
    print(f"{a.method}, {n} queries, {len(a.a)} A runs, {len(a.b)} B runs, {a.resamples} resamples (seed {a.seed})")
    print("| measure | A | B | B - A | 95% interval (paired bootstrap over queries) |")
    print("|---|---|---|---|---|")
    for m, r in out["measures"].items():
        print(f"| {m} | {r['a']:.3f} | {r['b']:.3f} | {r['difference']:+.3f} | "
              f"[{r['interval'][0]:+.3f}, {r['interval'][1]:+.3f}] |")


if __name__ == "__main__":
    main()
