# SPDX-License-Identifier: GPL-3.0-or-later
"""Candidate fusion rules for two methods of finished `canonform retrieve` runs (no recomputation).

usage: /usr/bin/python3 experiments/fused_rules.py CANONFORM RUN [RUN ...] [--target K] [--members A B]
           [--weights W ...] [--rules RULE,...] [--csv FILE]
Reads RUN/A/distances.bin and RUN/B/distances.bin (default A = none, B = euclidean-N) of every
RUN, and for each rule and each weight W of B (default 0.5 0.6 0.7 0.75 0.8 0.85 0.875 0.9 0.925
0.95; A gets 1 - W) forms the fused matrix, scores it with `CANONFORM evaluate --json` (the
classes of RUN/A/models.csv) and picks the weight that maximises the smaller of the first-tier
margins over the better member (the larger first tier of the two raw matrices) on the first K
runs (default 2, or fewer if fewer runs; the other runs are only reported; ties go to the lower
weight). Prints a markdown table: the two members alone, then per rule its best weight, first
tier / mean of the five measures (NN, 1-Tier, 2-Tier, E, DCG) per run, the smaller margin (from
the unrounded first tiers) and the first tier of B alone put through the rule (the rule at W = 1).
--csv FILE writes every scored matrix: rule,w_B,run,nn,first_tier,second_tier,e_measure,dcg,mean.

Rules (D an n x n distance matrix, a row = one query, the query itself left out of every row
statistic; every fused matrix is symmetrised, (F + F^T) / 2, and shifted so that its smallest
off-diagonal entry is 0):
  global-median  D / median of the off-diagonal entries (`fused-median:` of the tool)
  global-z       (D - mean) / sd of the off-diagonal entries
  row-median     D(i,j) / median of row i
  row-z          (D(i,j) - mean of row i) / sd of row i (`fused:` of the tool)
  row-minmax     (D(i,j) - min of row i) / (max - min of row i)
  row-knn5       D(i,j) / distance of i to its 5th nearest
  local-scaling5, local-scaling10   D(i,j) / sqrt(s_i s_j), s_i the distance to the k-th nearest
  rank-sum       rank of j in row i / (n - 1)
  rrf10, rrf60   reciprocal-rank fusion: -(k + 1) / (k + rank of j in row i)
  distinct1, distinct5   row-z with per-query weights: member m weighs w_m r_m(i) / sum w r(i),
                 r_m(i) = 1 - (distance to the k-th nearest) / (median distance) in row i
  recip1, recip5 the same with r_m(i) = share of i's k nearest that have i among their k nearest
  diffusion5, diffusion10   row-z fused, then the graph of each model's k nearest (and itself)
                 under it, rows normalised to W, similarity S = W W^T, distance max(S) - S
                 (plus 0.001 times the row-z fused matrix to break ties)
The rules were first compared with SIFT `opencv` by scripts outside the repository; this tool
is those scripts consolidated (same rules, weights and selection).
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from run_matrices import load_method

WEIGHTS = [0.5, 0.6, 0.7, 0.75, 0.8, 0.85, 0.875, 0.9, 0.925, 0.95]


def off(n):
    return ~np.eye(n, dtype=bool)


def row_sorted(D):
    """Each row's off-diagonal distances, ascending (n x n-1)."""
    n = D.shape[0]
    return np.sort(np.where(off(n), D, np.inf), axis=1)[:, :n - 1]


def ranks(D):
    """Rank of j in row i: the query itself 0, its nearest 1, ..., n - 1."""
    n = D.shape[0]
    X = np.where(off(n), D, -np.inf)
    return np.argsort(np.argsort(X, axis=1, kind="stable"), axis=1, kind="stable").astype(float)


def global_median(D):
    return D / np.median(D[off(D.shape[0])])


def global_z(D):
    v = D[off(D.shape[0])]
    return (D - v.mean()) / v.std()


def row_median(D):
    return D / np.median(row_sorted(D), axis=1)[:, None]


def row_z(D):
    S = row_sorted(D)
    return (D - S.mean(1)[:, None]) / S.std(1)[:, None]


def row_minmax(D):
    S = row_sorted(D)
    return (D - S[:, :1]) / (S[:, -1] - S[:, 0])[:, None]


def row_knn(k):
    return lambda D: D / row_sorted(D)[:, k - 1][:, None]


def local_scaling(k):
    def f(D):
        s = row_sorted(D)[:, k - 1]
        return D / np.sqrt(np.outer(s, s))
    return f


def rank_sum(D):
    return ranks(D) / (D.shape[0] - 1)


def rrf(k):
    return lambda D: -(k + 1) / (k + ranks(D))


def sym(F):
    F = 0.5 * (F + F.T)
    F = F - F[off(F.shape[0])].min()
    np.fill_diagonal(F, 0)
    return F


def weighted(normalise):
    return lambda Da, Db, w: sym((1 - w) * normalise(Da) + w * normalise(Db))


def distinctness(k):
    def r(D):
        S = row_sorted(D)
        return 1 - S[:, k - 1] / np.median(S, axis=1)
    return r


def reciprocity(k):
    def r(D):
        n = D.shape[0]
        nearest = np.argsort(np.where(off(n), D, np.inf), axis=1, kind="stable")[:, :k]
        A = np.zeros((n, n), dtype=bool)
        A[np.repeat(np.arange(n), k), nearest.ravel()] = True
        return (A & A.T).sum(1) / k
    return r


def per_query_weights(reliability):
    def f(Da, Db, w):
        wa = (1 - w) * np.maximum(reliability(Da), 1e-6)
        wb = w * np.maximum(reliability(Db), 1e-6)
        s = wa + wb
        return sym((wa / s)[:, None] * row_z(Da) + (wb / s)[:, None] * row_z(Db))
    return f


def diffusion(k):
    def f(Da, Db, w):
        F = weighted(row_z)(Da, Db, w)
        n = F.shape[0]
        nearest = np.argsort(np.where(off(n), F, np.inf), axis=1, kind="stable")[:, :k]
        W = np.zeros((n, n))
        W[np.repeat(np.arange(n), k), nearest.ravel()] = 1
        W += np.eye(n)
        W /= W.sum(1, keepdims=True)
        S = W @ W.T
        return sym(S.max() - S + 1e-3 * F)
    return f


RULES = [
    ("global-median", "global median (`fused-median:`)", weighted(global_median)),
    ("global-z", "global z-score", weighted(global_z)),
    ("row-median", "row median", weighted(row_median)),
    ("row-z", "row z-score (`fused:`)", weighted(row_z)),
    ("row-minmax", "row min-max", weighted(row_minmax)),
    ("row-knn5", "row / distance to the 5th neighbour", weighted(row_knn(5))),
    ("local-scaling5", "local scaling, k = 5", weighted(local_scaling(5))),
    ("local-scaling10", "local scaling, k = 10", weighted(local_scaling(10))),
    ("rank-sum", "sum of ranks", weighted(rank_sum)),
    ("rrf10", "reciprocal-rank fusion, k = 10", weighted(rrf(10))),
    ("rrf60", "reciprocal-rank fusion, k = 60", weighted(rrf(60))),
    ("distinct1", "row z-score, per-query weights x distinctness, k = 1", per_query_weights(distinctness(1))),
    ("distinct5", "row z-score, per-query weights x distinctness, k = 5", per_query_weights(distinctness(5))),
    ("recip1", "row z-score, per-query weights x reciprocity, k = 1", per_query_weights(reciprocity(1))),
    ("recip5", "row z-score, per-query weights x reciprocity, k = 5", per_query_weights(reciprocity(5))),
    ("diffusion5", "row z-score, then kNN-graph diffusion, k = 5", diffusion(5)),
    ("diffusion10", "row z-score, then kNN-graph diffusion, k = 10", diffusion(10)),
]


def load(run, method):
    return load_method(os.path.join(run, method))


MEASURES = ("nn", "first_tier", "second_tier", "e_measure", "dcg")


def member_pair(run, a, b, labels):
    """Members a and b of RUN on the models both have (in a's order): (D_a, D_b); writes their
    classes to the labels file LABELS for `canonform evaluate`."""
    na, classes, Da = load(run, a)
    nb, _, Db = load(run, b)
    common = [n for n in na if n in set(nb)]
    ia, ib = [na.index(n) for n in common], [nb.index(n) for n in common]
    with open(labels, "w") as f:
        f.write("path,class\n" + "".join("%s,%s\n" % (n, classes[n]) for n in common))
    return Da[np.ix_(ia, ia)], Db[np.ix_(ib, ib)]


def evaluate(cf, F, labels, tmp, who):
    """The micro-averaged measures of distance matrix F ({measure: value}, MEASURES) by
    `CF evaluate --json`; the script WHO ends with the tool's message if it fails."""
    mat = os.path.join(tmp, "fused.bin")
    np.asarray(F, dtype="<f4").tofile(mat)
    p = subprocess.run([cf, "evaluate", mat, "--labels", labels, "--json"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("%s: %s evaluate failed: %s" % (who, cf, p.stderr.strip()))
    j = json.loads(p.stdout)["micro"]
    return {k: j[k] for k in MEASURES}


def parse(argv):
    opts = {"target": None, "members": ["none", "euclidean-N"], "weights": None, "rules": None, "csv": None}
    pos = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--target":
            opts["target"] = int(argv[i + 1]); i += 2
        elif a == "--members":
            opts["members"] = argv[i + 1:i + 3]; i += 3
        elif a == "--rules":
            opts["rules"] = argv[i + 1].split(","); i += 2
        elif a == "--csv":
            opts["csv"] = argv[i + 1]; i += 2
        elif a == "--weights":
            i += 1
            opts["weights"] = []
            while i < len(argv) and not argv[i].startswith("--"):
                opts["weights"].append(float(argv[i])); i += 1
        elif a.startswith("--"):
            sys.exit("unknown option " + a + "\n" + __doc__)
        else:
            pos.append(a); i += 1
    if len(pos) < 2:
        sys.exit(__doc__)
    known = [r[0] for r in RULES]
    for r in opts["rules"] or []:
        if r not in known:
            sys.exit("unknown rule %s (rules: %s)" % (r, ", ".join(known)))
    return pos[0], pos[1:], opts


def main():
    cf, runs, opts = parse(sys.argv[1:])
    a, b = opts["members"]
    weights = opts["weights"] or WEIGHTS
    target = min(opts["target"] or 2, len(runs))
    rules = [r for r in RULES if opts["rules"] is None or r[0] in opts["rules"]]
    csv_rows = []
    with tempfile.TemporaryDirectory() as tmp:
        data = []
        for k, run in enumerate(runs):
            labels = os.path.join(tmp, "labels%d.csv" % k)
            data.append(member_pair(run, a, b, labels) + (labels,))

        def score(F, labels):
            m = list(evaluate(cf, F, labels, tmp, "fused_rules.py").values())
            return m + [sum(m) / 5]

        def cells(scores):
            return " | ".join("%.3f / %.3f" % (s[1], s[5]) for s in scores)

        names = [os.path.basename(os.path.normpath(r)) for r in runs]
        print("| rule (members: %s, %s) | weight of %s | %s | smaller margin (%s) | %s alone through the rule: %s 1-Tier |"
              % (a, b, b, " | ".join(names), ", ".join(names[:target]), b, " / ".join(names)))
        print("|---|---|" + "---|" * len(runs) + "---|---|")
        raw_a = [score(Da, lab) for Da, Db, lab in data]
        raw_b = [score(Db, lab) for Da, Db, lab in data]
        for member, scores in ((a, raw_a), (b, raw_b)):
            print("| %s alone | - | %s | - | - |" % (member, cells(scores)), flush=True)
            for run, s in zip(names, scores):
                csv_rows.append([member + " alone", "-", run] + s)
        base = [max(sa[1], sb[1]) for sa, sb in zip(raw_a, raw_b)]
        for rule, title, fuse in rules:
            best = None
            for w in weights:
                s = [score(fuse(Da, Db, w), lab) for Da, Db, lab in data]
                for run, sk in zip(names, s):
                    csv_rows.append([rule, "%.3f" % w, run] + sk)
                margin = min(s[k][1] - base[k] for k in range(target))
                if best is None or margin > best[0] + 1e-9:
                    best = (margin, w, s)
            margin, w, s = best
            alone = [score(fuse(Da, Db, 1.0), lab) for Da, Db, lab in data]
            for run, sk in zip(names, alone):
                csv_rows.append([rule, "1.000", run] + sk)
            print("| %s | %g | %s | %+.3f | %s |" % (title, w, cells(s), margin, " / ".join("%.3f" % x[1] for x in alone)),
                  flush=True)
    if opts["csv"]:
        with open(opts["csv"], "w") as f:
            f.write("rule,w_%s,run,nn,first_tier,second_tier,e_measure,dcg,mean\n" % b)
            for r in csv_rows:
                f.write(",".join(r[:3] + ["%.6f" % x for x in r[3:]]) + "\n")


if __name__ == "__main__":
    main()
