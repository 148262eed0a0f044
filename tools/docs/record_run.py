# SPDX-License-Identifier: GPL-3.0-or-later
"""Records the measures of a retrieval run folder as a result file the documentation shows.

usage: /usr/bin/python3 tools/docs/record_run.py RUN OUT.json --command "canonform retrieve ..." \
           --conditions "SIFT ..., codebook seed ..., 2 threads" [--title TITLE] [--methods M1,M2,...]
       /usr/bin/python3 tools/docs/record_run.py --reformat FILE.json...

RUN is a folder written by `canonform retrieve` (or a sharded run): every RUN/METHOD/metrics.json
(the micro-averaged measures, the pose consistency) and RUN/METHOD/timings.json (stage seconds)
becomes one row, methods in the order of --methods (default: the order of RUN/report.md's table).
OUT.json (under bench/results/retrieval/) is what a `<!-- generated: record FILE -->` block of a
docs page shows, with the command and conditions in one line; tools/docs/generate.py then rewrites
the page. The conditions say how the run was made (extractor, seed, threads), in words a reference
page can show; when, on which build and under what load go to the file's "provenance" (the build,
the date and the load average are added by this script), which only record pages (docs/records/)
show. One row per line, so that a re-measurement shows in `git diff` as the rows that changed.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

MEASURES = [("nn", "NN"), ("first_tier", "1-Tier"), ("second_tier", "2-Tier"), ("e_measure", "E-measure"),
            ("dcg", "DCG")]
SECONDS = [("forms_and_views", "forms+views s"), ("codebook", "codebook s"), ("distances_and_measures", "dist s")]
ORDER = ["title", "command", "conditions", "source", "provenance", "columns", "rows"]


def dump(record):
    """The record as JSON text: one column and one row per line."""
    lines = ["{"]
    keys = [k for k in ORDER if k in record] + [k for k in record if k not in ORDER]
    for i, k in enumerate(keys):
        comma = "," if i + 1 < len(keys) else ""
        v = record[k]
        if isinstance(v, list):
            items = [" " * 2 + json.dumps(x, ensure_ascii=False) for x in v]
            lines.append(f" {json.dumps(k)}: [\n" + ",\n".join(items) + f"\n ]{comma}")
        else:
            lines.append(f" {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}{comma}")
    lines.append("}")
    return "\n".join(lines) + "\n"


def methods_of(run):
    """Method folders in the order of RUN/report.md's table, else sorted."""
    found = sorted(d for d in os.listdir(run) if os.path.isfile(os.path.join(run, d, "metrics.json")))
    report = os.path.join(run, "report.md")
    if os.path.isfile(report):
        listed = re.findall(r"^\| ([^ |]+) \|", open(report).read(), re.M)
        ordered = [m for m in listed if m in found]
        return ordered + [m for m in found if m not in ordered]
    return found


def record(run, methods):
    rows, have_pose, have_seconds = [], False, set()
    for m in methods:
        with open(os.path.join(run, m, "metrics.json")) as f:
            metrics = json.load(f)
        row = {"method": m}
        micro = metrics.get("micro") or {}
        for k, _ in MEASURES:
            if k in micro:
                row[k] = round(micro[k], 6)
        if metrics.get("pose_consistency") is not None and metrics.get("pose_consistency_pairs", 1):
            row["pose_consistency"] = round(metrics["pose_consistency"], 6)
            have_pose = True
        timings = os.path.join(run, m, "timings.json")
        if os.path.isfile(timings):
            with open(timings) as f:
                seconds = json.load(f).get("seconds", {})
            for k, _ in SECONDS:
                if k in seconds:
                    row[k] = round(seconds[k], 2)
                    have_seconds.add(k)
        rows.append(row)
    columns = [{"key": "method", "title": "method"}]
    columns += [{"key": k, "title": t, "best": "max", "digits": 3} for k, t in MEASURES]
    if have_pose:
        columns.append({"key": "pose_consistency", "title": "pose consistency", "best": "min", "digits": 3})
    columns += [{"key": k, "title": t, "digits": 1} for k, t in SECONDS if k in have_seconds]
    return columns, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", nargs="?")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--command")
    ap.add_argument("--conditions")
    ap.add_argument("--title")
    ap.add_argument("--methods")
    ap.add_argument("--reformat", nargs="+", metavar="FILE")
    a = ap.parse_args()
    if a.reformat:
        for path in a.reformat:
            with open(path) as f:
                rec = json.load(f)
            with open(path, "w") as f:
                f.write(dump(rec))
        return
    if not (a.run and a.out and a.command and a.conditions):
        ap.error("RUN, OUT.json, --command and --conditions are needed")
    methods = a.methods.split(",") if a.methods else methods_of(a.run)
    if not methods:
        sys.exit(f"record_run.py: {a.run} has no METHOD/metrics.json: is it a retrieval run folder?")
    columns, rows = record(a.run, methods)
    old = {}
    if os.path.isfile(a.out):
        with open(a.out) as f:
            old = json.load(f)
    here = os.path.dirname(os.path.abspath(__file__))
    build = subprocess.run(["git", "-C", here, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    provenance = (f"build {build.strip() or 'unknown'}, recorded {time.strftime('%Y-%m-%d', time.gmtime())} "
                  f"(load average {load} then); recorded from the run folder by tools/docs/record_run.py")
    rec = {"title": a.title or old.get("title") or os.path.basename(os.path.abspath(a.run)),
           "command": a.command, "conditions": a.conditions, "provenance": provenance,
           "columns": columns, "rows": rows}
    with open(a.out, "w") as f:
        f.write(dump(rec))
    print(f"record_run.py: {len(rows)} methods of {a.run} -> {a.out}")


if __name__ == "__main__":
    main()
