# SPDX-License-Identifier: GPL-3.0-or-later
"""Nearest neighbour of two retrieval runs compared query by query (exact McNemar test).

usage: /usr/bin/python3 experiments/paired_nn.py A_DIR B_DIR [A_DIR B_DIR ...]
Each DIR is a method folder of a finished `canonform retrieve` run (RUN/METHOD, holding
distances.bin and models.csv); the pairs are, e.g., the same method with two SIFT backends, one
pair per seed. For each pair it prints both NN scores, the discordant queries (right with A only,
right with B only) and the two-sided exact binomial (McNemar) p-value of that split; over all
pairs, how many queries each side gets right in a majority of the pairs, and how many queries
have the same outcome in every pair on both sides. Queries are the models of models.csv (every
model is a query, its nearest other model decides), so both folders must list the same models.
"""
import math
import sys

import numpy as np

from run_matrices import load_method


def nn_hits(folder):
    names, classes, D = load_method(folder)
    labels = np.array([classes[n] for n in names])
    np.fill_diagonal(D, np.inf)
    return names, labels[D.argmin(axis=1)] == labels


def mcnemar_p(b, c):
    n, k = b + c, min(b, c)
    if n == 0:
        return 1.0
    return min(1.0, 2 * sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n)


def main(args):
    if len(args) < 2 or len(args) % 2:
        sys.exit(__doc__)
    A, B = [], []
    for a, b in zip(args[::2], args[1::2]):
        na, ha = nn_hits(a)
        nb, hb = nn_hits(b)
        if na != nb:
            sys.exit(f"{a} and {b} list different models")
        only_a, only_b = int((ha & ~hb).sum()), int((~ha & hb).sum())
        print(f"{a} vs {b}: NN {ha.mean():.3f} vs {hb.mean():.3f}; right with A only {only_a}, "
              f"with B only {only_b}; exact McNemar p = {mcnemar_p(only_a, only_b):.2f}")
        A.append(ha)
        B.append(hb)
    A, B = np.array(A), np.array(B)
    pairs = len(A)
    same = int(((A.all(0) | ~A.any(0)) & (B.all(0) | ~B.any(0)) & (A[0] == B[0])).sum())
    print(f"over {pairs} pairs: right in a majority of pairs A {int((A.sum(0) * 2 > pairs).sum())}, "
          f"B {int((B.sum(0) * 2 > pairs).sum())} of {A.shape[1]} queries; "
          f"same outcome in every pair on both sides: {same}")


if __name__ == "__main__":
    main(sys.argv[1:])
