# SPDX-License-Identifier: GPL-3.0-or-later
"""Test of experiments/paired_queries.py on run folders written here: per-query NN and first tier, the
difference of two set-ups and its bootstrap interval, and the refusal of runs of other models.
    paired_queries_test.py SOURCE_DIR"""
import csv
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_report import Report  # noqa: E402

src = sys.argv[1]
tool = os.path.join(src, "experiments", "paired_queries.py")
report = Report()
print("experiments/paired_queries.py")
classes = [c for c in "abc" for _ in range(4)]  # 3 classes of 4 models
n = len(classes)


def write_run(folder, D, labels=classes):
    os.makedirs(os.path.join(folder, "euclidean-N"))
    with open(os.path.join(folder, "euclidean-N", "models.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["name", "class"])
        w.writerows([f"m{i}", c] for i, c in enumerate(labels))
    with open(os.path.join(folder, "euclidean-N", "distances.csv"), "w", newline="") as f:
        csv.writer(f).writerows(D)


def run(*args):
    p = subprocess.run(["/usr/bin/python3", tool, "--json", "--resamples", "500", *args], capture_output=True, text=True)
    return p.returncode, (json.loads(p.stdout) if p.returncode == 0 else p.stderr)


with tempfile.TemporaryDirectory() as tmp:
    # perfect: same class at 1, others at 2; swapped: model 0's and model 4's classes look exchanged
    perfect = [[0 if i == j else (1 if classes[i] == classes[j] else 2) for j in range(n)] for i in range(n)]
    swap = list(range(n))
    swap[0], swap[4] = 4, 0
    swapped = [[perfect[swap[i]][swap[j]] for j in range(n)] for i in range(n)]
    write_run(os.path.join(tmp, "p"), perfect)
    write_run(os.path.join(tmp, "s"), swapped)
    rc, r = run("--a", os.path.join(tmp, "p"), "--b", os.path.join(tmp, "p"))
    report.check(rc == 0 and all(
        m["difference"] == 0 and m["interval"] == [0, 0] for m in r["measures"].values()), "a set-up against itself: difference 0, interval [0, 0]", r)
    report.check(rc == 0 and r["measures"]["nn"]["a"] == 1 and
                 r["measures"]["first_tier"]["a"] == 1, "a perfect matrix: NN 1, first tier 1", r)
    rc, r = run("--a", os.path.join(tmp, "p"), "--b", os.path.join(tmp, "s"))
    # Swapped: models 0 and 4 sit among the other class (NN 0, first tier 0); every other model of
    # classes a and b has 2 class mates and one stranger at distance 1 (first tier 2/3), and its
    # NN is the lowest index of them (ties by index): a class mate for 1, 2, 3, model 0 for 5, 6,
    # 7; class c is untouched. NN 7/12.
    ft = (2 * 0 + 6 * (2 / 3) + 4 * 1) / n
    report.check(rc == 0 and abs(r["measures"]["nn"]["b"] - 7 / 12) < 1e-12 and
                 abs(r["measures"]["first_tier"]["b"] - ft) < 1e-12, "swapped: NN and first tier per query as counted by hand", r)
    report.check(rc == 0 and r["measures"]["first_tier"]["difference"] < 0 and
                 r["measures"]["first_tier"]["interval"][1] < 0, "swapped - perfect: negative, interval below 0 for the first tier", r)
    write_run(os.path.join(tmp, "other"), perfect, labels=sorted(classes, reverse=True))
    rc, err = run("--a", os.path.join(tmp, "p"), "--b", os.path.join(tmp, "other"))
    report.check(rc != 0 and "same models" in err, "runs of other models refused, saying so", err)
sys.exit(report.exit_code())
