# SPDX-License-Identifier: GPL-3.0-or-later
"""Shape and pose in a `canonform retrieve` run, measured with ground-truth correspondences.

usage: /usr/bin/python3 experiments/correspondence_analysis.py RUN DATASET [--pose-of REGEX]

For every method of RUN whose forms are in correspondence (DATASET/corres/NAME.vts: line k = the
1-based vertex at template point k, the same template for every model), every pair of forms is
aligned by the best rigid motion or mirror image (Kabsch) and their distance is the RMS distance
between corresponding points relative to the RMS radius of the second (the measure of the run's
pose consistency, here over all pairs). Writes RUN/METHOD/correspondence_distances.csv (an
N x N matrix in RUN/METHOD/models.csv order) and prints per method:
  - same class, other pose: what is left of the pose (the run's pose consistency);
  - other class, same pose (needs --pose-of): the shape difference between classes;
  - their ratio (> 1: the pose left over is larger than the shape difference between classes);
  - NN and first tier of the correspondence distances with the class labels, and (with
    --pose-of) with the pose as the label: which of shape and pose the forms still encode.
--pose-of REGEX: a regular expression whose first group, applied to a model's name, gives its
pose number, taken modulo 10 (FAUST: 'tr_reg_(\\d+)': the pose is the index modulo 10).
"""
import csv
import os
import re
import struct
import sys

import numpy as np


def read_ply_vertices(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    n, props, fmt = 0, [], None
    in_vertex = False
    for line in header:
        w = line.split()
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            in_vertex = w[1] == "vertex"
            if in_vertex:
                n = int(w[2])
        elif w[0] == "property" and in_vertex:
            props.append(w[1])
    if fmt != "binary_little_endian":
        raise SystemExit(f"{path}: only binary little-endian PLY is read here")
    kinds = {"double": "f8", "float": "f4", "float32": "f4", "float64": "f8"}
    dt = np.dtype([(f"p{i}", "<" + kinds[p]) for i, p in enumerate(props)])
    v = np.frombuffer(data, dtype=dt, count=n, offset=end)
    return np.stack([v["p0"], v["p1"], v["p2"]], axis=1).astype(np.float64)


def aligned_rms(P, Q):
    """RMS of Q - (R P + t) for the best rotation or reflection R, relative to Q's RMS radius."""
    p = P - P.mean(0)
    q = Q - Q.mean(0)
    u, s, vt = np.linalg.svd(p.T @ q)
    # best orthogonal map (rotation or mirror image): trace term = sum of singular values
    residual = max(0.0, (p * p).sum() + (q * q).sum() - 2 * s.sum())
    return np.sqrt(residual / len(P)) / np.sqrt((q * q).sum() / len(Q))


def nn_and_first_tier(D, labels):
    labels = np.asarray(labels)
    n = len(labels)
    nn, ft = [], []
    for i in range(n):
        order = [j for j in np.argsort(D[i], kind="stable") if j != i]
        c = int((labels == labels[i]).sum()) - 1
        if c < 2:
            continue
        nn.append(labels[order[0]] == labels[i])
        ft.append(sum(labels[j] == labels[i] for j in order[:c]) / c)
    return float(np.mean(nn)), float(np.mean(ft))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    run, dataset = sys.argv[1], sys.argv[2]
    pose_re = None
    if "--pose-of" in sys.argv:
        pose_re = re.compile(sys.argv[sys.argv.index("--pose-of") + 1])
    for method in sorted(os.listdir(run)):
        models_csv = os.path.join(run, method, "models.csv")
        if not os.path.isfile(models_csv):
            continue
        with open(models_csv) as f:
            rows = list(csv.DictReader(f))
        names = [r["name"] for r in rows]
        labels = [r["class"] for r in rows]
        pts = []
        for name in names:
            vts = os.path.join(dataset, "corres", name + ".vts")
            if not os.path.isfile(vts):
                break
            idx = np.loadtxt(vts, dtype=int) - 1
            V = read_ply_vertices(os.path.join(run, method, "forms", name + ".ply"))
            pts.append(V[idx])
        if len(pts) != len(names):
            print(f"{method}: not every model has correspondences; skipped")
            continue
        n = len(names)
        D = np.zeros((n, n))
        for i in range(n):
            for j in range(i + 1, n):
                D[i, j] = aligned_rms(pts[i], pts[j])
                D[j, i] = aligned_rms(pts[j], pts[i])
        np.savetxt(os.path.join(run, method, "correspondence_distances.csv"), D, delimiter=",", fmt="%.6f")
        lab = np.asarray(labels)
        same = lab[:, None] == lab[None, :]
        off = ~np.eye(n, dtype=bool)
        within = D[same & off].mean()
        line = f"{method}: same class, other pose {within:.3f}"
        if pose_re:
            pose = np.array([int(pose_re.search(x).group(1)) % 10 for x in names])
            same_pose = pose[:, None] == pose[None, :]
            between = D[~same & same_pose].mean()
            line += f"; other class, same pose {between:.3f}; ratio {within / between:.2f}"
        nn, ft = nn_and_first_tier(D, labels)
        line += f"; by class NN {nn:.3f} 1-tier {ft:.3f}"
        if pose_re:
            nn_p, ft_p = nn_and_first_tier(D, pose)
            line += f"; by pose NN {nn_p:.3f} 1-tier {ft_p:.3f}"
        print(line, flush=True)


main()
