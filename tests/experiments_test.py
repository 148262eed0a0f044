# SPDX-License-Identifier: GPL-3.0-or-later
"""Smoke tests of the analysis scripts in experiments/ (ctest experiments.NAME): each runs its script
on a tiny input written here - run folders of a few models whose distances, metrics and forms are
chosen so that the right output is known - and checks the output. One mode per script.

usage: /usr/bin/python3 tests/experiments_test.py NAME --source DIR --work DIR [--canonform CANONFORM]

The shell sweeps (beta_sweep.sh, noise_sweep.sh) run `canonform retrieve`, which is the tool's to
test (cli.end_to_end): here they run a stand-in CANONFORM that records its arguments and writes, for
each method it is asked for, a metrics.json whose measures follow from the method and the noise.
So the test checks the sweep itself: the retrieve calls it makes, the table and the plot it writes.
fused_rules.py and fused_defaults.py score with the real tool's `canonform evaluate`.
"""
import argparse
import csv
import json
import os
import re
import shutil
import struct
import subprocess
import sys

sys.dont_write_bytecode = True  # the scripts are imported from the source tree: no __pycache__ there
os.environ["PYTHONDONTWRITEBYTECODE"] = "1"  # nor from the scripts the tests run
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_report import Report  # noqa: E402

MEASURES = ["nn", "first_tier", "second_tier", "e_measure", "dcg"]
report = Report()


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


def write_method(folder, names, classes, D, metrics=None):
    """A method folder of a finished run: models.csv, distances.bin (float32), distances.csv."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "models.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["name", "class"])
        w.writerows(zip(names, classes))
    with open(os.path.join(folder, "distances.bin"), "wb") as f:
        f.write(struct.pack("<%df" % (len(D) * len(D)), *[x for row in D for x in row]))
    with open(os.path.join(folder, "distances.csv"), "w", newline="") as f:
        csv.writer(f).writerows(D)
    if metrics is not None:
        with open(os.path.join(folder, "metrics.json"), "w") as f:
            json.dump(metrics, f)


def micro(base):
    return {m: round(base + 0.01 * k, 4) for k, m in enumerate(MEASURES)}


def script(a, name):
    return os.path.join(a.source, "experiments", name)


def stand_in(a):
    """A CANONFORM that answers `retrieve --dataset D --out RUN --method M,... [--noise S] ...` by writing
    RUN/FOLDER/metrics.json per method (measures from beta and noise) and logging its arguments."""
    path = os.path.join(a.work, "canonform_stand_in.py")
    with open(path, "w") as f:
        f.write('''import json, os, sys
args = sys.argv[1:]
with open(os.environ["STAND_IN_LOG"], "a") as log:
    log.write(json.dumps(args) + "\\n")
assert args[0] == "retrieve", args
opt = lambda k, d=None: args[args.index(k) + 1] if k in args else d
out, noise = opt("--out"), float(opt("--noise", 0))
for spec in opt("--method").split(","):
    base, _, beta = spec.partition(":beta=")
    folder = base + ("_beta" + beta if beta else "")
    value = 0.5 + (float(beta) / 1000 if beta else 0) - noise / 10 + (0.1 if base == "euclidean-N" else 0)
    os.makedirs(os.path.join(out, folder), exist_ok=True)
    metrics = {"method": folder, "base": base, "micro": {m: round(value + 0.01 * k, 4) for k, m in
               enumerate(["nn", "first_tier", "second_tier", "e_measure", "dcg"])}, "pose_consistency": 0.2}
    if beta:
        metrics["beta"] = float(beta)
    json.dump(metrics, open(os.path.join(out, folder, "metrics.json"), "w"))
print("| method | NN |")
''')
    sh = os.path.join(a.work, "canonform")
    with open(sh, "w") as f:
        f.write(f'#!/bin/sh\nexec /usr/bin/python3 "{path}" "$@"\n')
    os.chmod(sh, 0o755)
    return sh


# --- the modules -------------------------------------------------------------------------------
def test_run_matrices(a):
    sys.path.insert(0, os.path.join(a.source, "experiments"))
    from run_matrices import load_method
    D = [[0, 1, 2], [1, 0, 3], [2, 3, 0]]
    folder = os.path.join(a.work, "run", "euclidean-N")
    write_method(folder, ["m0", "m1", "m2"], ["a", "a", "b"], D)
    names, classes, M = load_method(folder)
    report.check(names == ["m0", "m1", "m2"] and classes == {"m0": "a", "m1": "a", "m2": "b"},
                 "load_method: the models and classes of models.csv, in matrix order")
    report.check(M.dtype.name == "float64" and M.tolist() == D, "load_method: the float32 matrix as float64")
    with open(os.path.join(folder, "distances.bin"), "ab") as f:
        f.write(b"\0\0\0\0")
    try:
        load_method(folder)
        report.check(False, "load_method refuses a matrix of the wrong size")
    except SystemExit as e:
        report.check("distances.bin has 10 entries, models.csv 3 models" in str(e),
                     f"load_method refuses a matrix of the wrong size: {e}")


def test_run_metrics(a):
    sys.path.insert(0, os.path.join(a.source, "experiments"))
    from run_metrics import MEASURES as measures, method_metrics
    r = os.path.join(a.work, "run")
    for m, v in (("none", 0.3), ("euclidean-N", 0.6)):
        os.makedirs(os.path.join(r, m))
        json.dump({"micro": micro(v)}, open(os.path.join(r, m, "metrics.json"), "w"))
    os.makedirs(os.path.join(r, "cache"))
    got = list(method_metrics(r))
    report.check([d for d, _ in got] == ["euclidean-N", "none"] and got[1][1]["micro"]["nn"] == 0.3,
                 "method_metrics: every method folder with a metrics.json, sorted; others skipped")
    report.check(measures == MEASURES, "the five measures in psbTable's order")


# --- Fig. 6: the beta sweep ---------------------------------------------------------------------
def check_beta_csv(path, expected):
    rows = list(csv.DictReader(open(path)))
    report.check([(r["variant"], float(r["beta"])) for r in rows] == expected,
                 f"beta_sweep.csv: one row per variant and beta, in order ({len(rows)})", str(rows))
    ok = all(abs(float(r["mean"]) - sum(float(r[m]) for m in MEASURES) / 5) < 1e-4 for r in rows)
    report.check(ok, "beta_sweep.csv: the mean is the mean of the five measures")
    return rows


def test_plot_beta(a):
    r = os.path.join(a.work, "run")
    for base, beta in (("euclidean-A", 5), ("euclidean-A", 10), ("euclidean-N", 65), ("euclidean-N", 130)):
        os.makedirs(os.path.join(r, f"{base}_beta{beta}"))
        json.dump({"base": base, "beta": beta, "micro": micro(0.5 + beta / 1000), "pose_consistency": 0.2},
                  open(os.path.join(r, f"{base}_beta{beta}", "metrics.json"), "w"))
    os.makedirs(os.path.join(r, "none"))
    json.dump({"base": "none", "micro": micro(0.3)}, open(os.path.join(r, "none", "metrics.json"), "w"))
    p = run(["/usr/bin/python3", script(a, "plot_beta.py"), r, "title"])
    report.check(p.returncode == 0, "plot_beta.py runs", p.stderr)
    rows = check_beta_csv(os.path.join(r, "beta_sweep.csv"), [("A", 5), ("A", 10), ("N", 65), ("N", 130)])
    report.check(rows and abs(float(rows[3]["mean"]) - 0.65) < 1e-4, "beta_sweep.csv: N at beta 130 (0.63 + 0.02)")
    report.check(is_png(os.path.join(r, "beta_sweep.png")), "beta_sweep.png written")
    report.check("best mean" not in p.stdout and "N beta=130: mean 0.650" in p.stdout, "the rows printed", p.stdout)
    p = run(["/usr/bin/python3", script(a, "plot_beta.py"), os.path.join(r, "none")])
    report.check(p.returncode != 0 and "no euclidean-A/N" in p.stderr, "a run without the variants is refused")


def test_beta_sweep(a):
    cf = stand_in(a)
    env = dict(os.environ, CANONFORM=cf, STAND_IN_LOG=os.path.join(a.work, "calls.log"))
    os.makedirs(os.path.join(a.work, "coll"))
    sweep = os.path.join(a.work, "sweep")
    p = run([script(a, "beta_sweep.sh"), os.path.join(a.work, "coll"), sweep, "--betas-a", "5 10", "--betas-n",
             "65 130", "--words", "50"], env=env)
    report.check(p.returncode == 0, "beta_sweep.sh runs", p.stderr)
    calls = [json.loads(x) for x in open(os.path.join(a.work, "calls.log"))]
    report.check(len(calls) == 1 and calls[0][calls[0].index("--method") + 1] ==
                 "euclidean-A:beta=5,euclidean-A:beta=10,euclidean-N:beta=65,euclidean-N:beta=130"
                 and calls[0][-2:] == ["--words", "50"], "one retrieve with every beta of both variants, the "
                 "other options passed on", str(calls))
    check_beta_csv(os.path.join(sweep, "beta_sweep.csv"), [("A", 5), ("A", 10), ("N", 65), ("N", 130)])
    report.check(is_png(os.path.join(sweep, "beta_sweep.png")), "beta_sweep.png written")


# --- Table 5: noise -----------------------------------------------------------------------------
def check_noise_csv(path, sigmas):
    rows = list(csv.DictReader(open(path)))
    want = [(s, m) for s in sigmas for m in ("euclidean-N", "none")]
    report.check([(float(r["sigma"]), r["method"]) for r in rows] == want,
                 "noise.csv: one row per sigma and method, in order", str(rows))
    ok = all(abs(float(r["mean"]) - sum(float(r[m]) for m in MEASURES) / 5) < 2e-3 for r in rows)
    report.check(ok, "noise.csv: the mean is the mean of the five measures")


def test_plot_noise(a):
    args = []
    for s in (0, 0.2):
        r = os.path.join(a.work, f"sigma_{s}")
        for m, v in (("none", 0.4), ("euclidean-N", 0.6)):
            os.makedirs(os.path.join(r, m))
            json.dump({"method": m, "micro": micro(v - s / 10)}, open(os.path.join(r, m, "metrics.json"), "w"))
        args.append(f"{s}={r}")
    out = os.path.join(a.work, "noise")
    p = run(["/usr/bin/python3", script(a, "plot_noise.py"), out] + args)
    report.check(p.returncode == 0, "plot_noise.py runs", p.stderr)
    check_noise_csv(out + ".csv", [0, 0.2])
    rows = list(csv.DictReader(open(out + ".csv")))
    report.check(rows[3]["nn"] == "0.380", "noise.csv: the measures of each run (none's NN at sigma 0.2)", str(rows[3]))
    report.check(is_png(out + ".png"), "noise.png written")


def test_noise_sweep(a):
    cf = stand_in(a)
    env = dict(os.environ, CANONFORM=cf, STAND_IN_LOG=os.path.join(a.work, "calls.log"))
    os.makedirs(os.path.join(a.work, "coll"))
    out = os.path.join(a.work, "noise")
    p = run([script(a, "noise_sweep.sh"), os.path.join(a.work, "coll"), out, "--sigmas", "0 0.2",
             "--method", "none,euclidean-N", "--simplify", "1000"], env=env)
    report.check(p.returncode == 0, "noise_sweep.sh runs", p.stderr)
    calls = [json.loads(x) for x in open(os.path.join(a.work, "calls.log"))]
    report.check([(c[c.index("--out") + 1], c[c.index("--noise") + 1]) for c in calls] ==
                 [(f"{out}/sigma_0", "0"), (f"{out}/sigma_0.2", "0.2")]
                 and all(c[-4:] == ["--method", "none,euclidean-N", "--simplify", "1000"] for c in calls),
                 "one retrieve per sigma into its own folder, the other options passed on", str(calls))
    check_noise_csv(os.path.join(out, "noise.csv"), [0, 0.2])
    report.check(is_png(os.path.join(out, "noise.png")), "noise.png written")


# --- paired comparisons -------------------------------------------------------------------------
LABELS = ["a", "a", "b", "b"]
NAMES = ["m0", "m1", "m2", "m3"]
RIGHT = [[0, 1, 5, 5], [1, 0, 5, 5], [5, 5, 0, 1], [5, 5, 1, 0]]   # every nearest neighbour of its class
WRONG2 = [[0, 5, 1, 5], [5, 0, 5, 1], [1, 5, 0, 5], [5, 1, 5, 0]]  # every one of the other class


def test_paired_nn(a):
    A, B = os.path.join(a.work, "A", "none"), os.path.join(a.work, "B", "none")
    write_method(A, NAMES, LABELS, RIGHT)
    write_method(B, NAMES, LABELS, WRONG2)
    p = run(["/usr/bin/python3", script(a, "paired_nn.py"), A, B])
    report.check(p.returncode == 0, "paired_nn.py runs", p.stderr)
    report.check("NN 1.000 vs 0.000; right with A only 4, with B only 0; exact McNemar p = 0.12" in p.stdout,
                 "NN of both, the discordant queries and the exact McNemar p (2 / 2^4)", p.stdout)
    report.check("right in a majority of pairs A 4, B 0 of 4 queries; same outcome in every pair on both sides: 0"
                 in p.stdout, "the summary over the pairs", p.stdout)
    C = os.path.join(a.work, "C", "none")
    write_method(C, ["x0", "x1", "x2", "x3"], LABELS, RIGHT)
    p = run(["/usr/bin/python3", script(a, "paired_nn.py"), A, C])
    report.check(p.returncode != 0 and "list different models" in p.stderr, "folders of other models are refused")


def fused_runs(a, count):
    """RUNs of two members over 6 models (classes a, b of 3): none finds class a (same-class distance 1, the
    other class at 3) but puts b's own class at 3.5; euclidean-N the other way round. Each member alone
    has NN 0.5; any fusion of the two with comparable weights finds both classes."""
    labels = ["a"] * 3 + ["b"] * 3
    names = [f"m{i}" for i in range(6)]

    runs = []
    for k in range(count):
        Dn = [[0 if i == j else (1 if labels[i] == "a" else 3.5 + 0.1 * k) if labels[i] == labels[j] else 3
               for j in range(6)] for i in range(6)]
        De = [[0 if i == j else (3.5 + 0.1 * k if labels[i] == "a" else 1) if labels[i] == labels[j] else 3
               for j in range(6)] for i in range(6)]
        r = os.path.join(a.work, f"run{k}")
        write_method(os.path.join(r, "none"), names, labels, Dn)
        write_method(os.path.join(r, "euclidean-N"), names, labels, De)
        runs.append(r)
    return runs


def test_fused_rules(a):
    runs = fused_runs(a, 2)
    out = os.path.join(a.work, "rules.csv")
    p = run(["/usr/bin/python3", script(a, "fused_rules.py"), a.canonform] + runs +
            ["--rules", "row-z,global-median", "--weights", "0.5", "0.9", "--csv", out])
    report.check(p.returncode == 0, "fused_rules.py runs", p.stderr)
    rows = list(csv.DictReader(open(out))) if os.path.isfile(out) else []
    score = {(r["rule"], r["w_euclidean-N"], r["run"]): r for r in rows}
    report.check(len(rows) == 2 * 2 + 2 * 3 * 2, f"--csv: each member alone, and every rule at each weight and at 1, "
                 f"per run ({len(rows)})")
    report.check(float(score.get(("none alone", "-", "run0"), {}).get("nn", -1)) == 0.5 and
                 float(score.get(("euclidean-N alone", "-", "run1"), {}).get("nn", -1)) == 0.5,
                 "each member alone: NN 0.5 (one class found)")
    report.check(all(float(score.get((rule, "0.500", run), {}).get("nn", -1)) == 1.0 for rule in ("row-z", "global-median")
                     for run in ("run0", "run1")), "both rules at equal weights find both classes: NN 1.0")
    report.check(float(score.get(("row-z", "1.000", "run0"), {}).get("nn", -1)) == 0.5,
                 "a rule at weight 1 is euclidean-N alone: NN 0.5")
    report.check("| row z-score (`fused:`) |" in p.stdout and "| global median (`fused-median:`) |" in p.stdout,
                 "the table names each rule", p.stdout)


def test_fused_defaults(a):
    runs = fused_runs(a, 2)
    out = os.path.join(a.work, "defaults.json")
    p = run(["/usr/bin/python3", script(a, "fused_defaults.py"), a.canonform, "--collection", "toy"] + runs +
            ["--rules", "row-z,rank-sum", "--weights", "0.5", "0.9", "--json", out, "--command", "C",
             "--conditions", "K"])
    report.check(p.returncode == 0, "fused_defaults.py runs", p.stderr)
    rec = json.load(open(out)) if os.path.isfile(out) else {}
    rows = rec.get("rows", [])
    report.check(rec.get("command") == "C" and rec.get("conditions") == "K" and len(rows) == 2 + 2 * 2,
                 f"--json: a results record of the members and the {2 * 2} candidates", json.dumps(rec)[:300])
    best = next((r for r in rows if r.get("rule") == "row-z" and r.get("weight") == 0.5), None)
    report.check(best is not None and best["worst"] > 0 and rows[2] == best,
                 "row-z at 0.5 beats both members on the toy collection and is ranked first", str(rows[:3]))


# --- correspondences ----------------------------------------------------------------------------
def write_ply(path, V):
    with open(path, "wb") as f:
        f.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\nproperty double x\n"
                f"property double y\nproperty double z\nend_header\n".encode())
        for v in V:
            f.write(struct.pack("<3d", *v))


def test_correspondence_analysis(a):
    import math
    template = [(0, 0, 0), (1, 0, 0), (0, 2, 0), (0, 0, 3), (1, 1, 0), (2, 0, 1), (0, 1, 2), (1, 2, 3)]
    shapes = {"thin": (1, 1, 1), "wide": (3, 1, 1), "tall": (1, 1, 3)}  # 3 poses each: poses are classes of 3 too
    run_dir, data = os.path.join(a.work, "run"), os.path.join(a.work, "data")
    os.makedirs(os.path.join(data, "corres"))
    names, labels = [], []
    for cls, (sx, sy, sz) in shapes.items():
        for pose in range(3):  # a pose: a rotation about z; the file's vertex order is turned by the pose
            c, s = math.cos(pose), math.sin(pose)
            pts = [(c * x * sx - s * y * sy, s * x * sx + c * y * sy, z * sz) for x, y, z in template]
            order = [(k + pose) % len(pts) for k in range(len(pts))]  # file vertex i = template point order[i]
            name = f"{cls}_{pose}"
            os.makedirs(os.path.join(run_dir, "none", "forms"), exist_ok=True)
            write_ply(os.path.join(run_dir, "none", "forms", name + ".ply"), [pts[order[i]] for i in range(len(pts))])
            with open(os.path.join(data, "corres", name + ".vts"), "w") as f:  # line k: vertex of template point k
                f.write("\n".join(str(order.index(k) + 1) for k in range(len(pts))) + "\n")
            names.append(name)
            labels.append(cls)
    write_method(os.path.join(run_dir, "none"), names, labels, [[0] * 9 for _ in range(9)])
    p = run(["/usr/bin/python3", script(a, "correspondence_analysis.py"), run_dir, data, "--pose-of", r"_(\d+)$"])
    report.check(p.returncode == 0, "correspondence_analysis.py runs", p.stderr)
    m = re.search(r"none: same class, other pose ([\d.]+); other class, same pose ([\d.]+); ratio ([\d.]+); "
                  r"by class NN ([\d.]+) 1-tier ([\d.]+); by pose NN ([\d.]+)", p.stdout)
    report.check(m is not None and float(m.group(1)) == 0 and float(m.group(2)) > 0.1,
                 "rotated copies align exactly (no pose left); the two shapes stay apart", p.stdout)
    report.check(m is not None and float(m.group(4)) == 1 and float(m.group(5)) == 1,
                 "by class: NN and first tier 1", p.stdout)
    D = [[float(x) for x in r] for r in csv.reader(open(os.path.join(run_dir, "none", "correspondence_distances.csv")))]
    report.check(len(D) == 9 and all(D[i][i] == 0 for i in range(9)), "correspondence_distances.csv: 9 x 9, 0 diagonal")


def main():
    tests = {k[5:]: v for k, v in globals().items() if k.startswith("test_")}
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("name", choices=sorted(tests))
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--canonform")
    a = ap.parse_args()
    a.work = os.path.join(a.work, a.name)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    print(f"experiments/{a.name}")
    tests[a.name](a)
    sys.exit(report.exit_code())


if __name__ == "__main__":
    main()
