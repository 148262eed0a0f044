# SPDX-License-Identifier: GPL-3.0-or-later
"""Records the measures of retrieval runs repeated over codebook seeds as a result file the
documentation shows (a `<!-- generated: record FILE -->` block; tools/docs/generate.py).

usage: /usr/bin/python3 tools/docs/record_seeds.py ROOT OUT.json --command "..." --conditions "..."
           [--title TITLE] [--collections tosca,procedural,...] [--backends a,b,...]
           [--methods none,euclidean-N] [--measures nn,first_tier]

ROOT holds one `canonform retrieve` run folder per collection, SIFT extractor and codebook seed:
ROOT/COLLECTION/BACKEND/seedS/METHOD/metrics.json (micro-averaged measures). Each row is one
collection, extractor and method: per measure the mean over the seeds found, the spread (largest
minus smallest) and the per-seed values in seed order. A run that has not finished (no
metrics.json) is left out, and the seeds column says which seeds a row has.
"""
import argparse
import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from record_run import dump  # noqa: E402

TITLES = {"nn": "NN", "first_tier": "1-Tier", "second_tier": "2-Tier", "e_measure": "E-measure", "dcg": "DCG"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("root")
    ap.add_argument("out")
    ap.add_argument("--command", required=True)
    ap.add_argument("--conditions", required=True)  # how (extractors, seeds, threads): reference pages show it
    ap.add_argument("--provenance", default="")  # builds, dates, loads: only record pages show it
    ap.add_argument("--title", default="")
    ap.add_argument("--collections", default="tosca,procedural,faust,shrec07")
    ap.add_argument("--backends", default="")
    ap.add_argument("--methods", default="none,euclidean-N")
    ap.add_argument("--measures", default="nn,first_tier")
    a = ap.parse_args()
    measures = a.measures.split(",")
    cols = [{"key": "collection", "title": "collection"}, {"key": "sift", "title": "SIFT"},
            {"key": "method", "title": "method"}, {"key": "seeds", "title": "seeds"}]
    for m in measures:
        t = TITLES.get(m, m)
        cols += [{"key": m, "title": t + " mean", "digits": 3}, {"key": m + "_spread", "title": t + " spread", "digits": 3},
                 {"key": m + "_seeds", "title": t + " per seed"}]
    rows = []
    for coll in a.collections.split(","):
        backends = a.backends.split(",") if a.backends else sorted(os.listdir(os.path.join(a.root, coll)))
        for b in backends:
            for method in a.methods.split(","):
                found = []
                for mf in sorted(glob.glob(os.path.join(a.root, coll, b, "seed*", method, "metrics.json"))):
                    seed = int(os.path.basename(os.path.dirname(os.path.dirname(mf)))[4:])
                    found.append((seed, json.load(open(mf))["micro"]))
                if not found:
                    continue
                found.sort(key=lambda x: x[0])
                row = {"collection": coll, "sift": b, "method": method, "seeds": ",".join(str(s) for s, _ in found)}
                for m in measures:
                    v = [x[m] for _, x in found]
                    row[m] = round(sum(v) / len(v), 4)
                    row[m + "_spread"] = round(max(v) - min(v), 4)
                    row[m + "_seeds"] = " ".join(f"{x:.3f}" for x in v)
                rows.append(row)
    rec = {"title": a.title, "command": a.command, "conditions": a.conditions, "columns": cols, "rows": rows}
    if a.provenance:
        rec["provenance"] = a.provenance
    if not rec["title"]:
        del rec["title"]
    with open(a.out, "w") as f:
        f.write(dump(rec))
    print(f"{a.out}: {len(rows)} rows")


if __name__ == "__main__":
    main()
