#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Compares two runs of the same filters (portable archive against today's build) to a relative tolerance.

    portable_compare.py [--rel 1e-6] A:B...

Each A:B is a pair of files of the same kind:
  .json   every number of B equal to A's within rel * max(|a|, 1e-300) (integers and booleans
          exactly); keys ending in "seconds" (timings) are skipped; a "residual" (a solver's relative
          residual, round-off of size 1e-14 whose digits are noise) must be below 1e-9 in both;
          strings equal;
  .ply    every vertex property (ASCII or binary little-endian PLY): max |a - b| <= rel * max |a|
          per property, and the same vertex and face counts;
  .cfvd   (descriptor files) byte for byte.
Prints one line per pair and 'N passed, N failed'.
"""
import json
import math
import struct
import sys

from check_report import Report

PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
             "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
             "double": "d", "float64": "d"}


def read_ply(path):
    """{property: [values]} of the vertex element, and the element counts."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
            if not line and f.tell() > 1 << 20:
                raise ValueError(f"{path}: no end_header")
        body = f.read()
    fmt = next(l.split()[1] for l in header if l.startswith("format"))
    elements = []  # (name, count, [(prop, type or ('list', count type, item type))])
    for l in header:
        w = l.split()
        if w and w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w and w[0] == "property":
            elements[-1][2].append((w[-1], tuple(w[2:4]) if w[1] == "list" else w[1]))
    counts = {e[0]: e[1] for e in elements}
    vertex = {}
    if fmt == "ascii":
        tokens = body.split()
        at = 0
        for name, count, props in elements:
            for _ in range(count):
                for p, t in props:
                    if isinstance(t, tuple):
                        n = int(tokens[at]); at += 1 + n
                    else:
                        if name == "vertex":
                            vertex.setdefault(p, []).append(float(tokens[at]))
                        at += 1
            if name == "vertex":
                break
    elif fmt == "binary_little_endian":
        at = 0
        for name, count, props in elements:
            if any(isinstance(t, tuple) for _, t in props):
                break  # the vertex element comes first in every file compared here
            rec = "<" + "".join(PLY_TYPES[t] for _, t in props)
            size = struct.calcsize(rec)
            for i in range(count):
                values = struct.unpack_from(rec, body, at)
                at += size
                if name == "vertex":
                    for (p, _), v in zip(props, values):
                        vertex.setdefault(p, []).append(float(v))
            if name == "vertex":
                break
    else:
        raise ValueError(f"{path}: PLY format {fmt} not read here")
    return vertex, counts


def compare_numbers(a, b, rel, where, problems):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k.endswith("seconds"):
                continue
            if k == "residual" and k in a and k in b:
                if not (abs(a[k]) < 1e-9 and abs(b[k]) < 1e-9):
                    problems.append(f"{where}{k}: {a[k]!r} vs {b[k]!r} (not both below 1e-9)")
                continue
            if k not in a or k not in b:
                problems.append(f"{where}{k}: only in one")
            else:
                compare_numbers(a[k], b[k], rel, f"{where}{k}.", problems)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            problems.append(f"{where}: {len(a)} vs {len(b)} values")
        else:
            for i, (x, y) in enumerate(zip(a, b)):
                compare_numbers(x, y, rel, f"{where}[{i}]", problems)
    elif isinstance(a, bool) or isinstance(b, bool) or isinstance(a, str) or isinstance(b, str):
        if a != b:
            problems.append(f"{where}: {a!r} vs {b!r}")
    elif isinstance(a, int) and isinstance(b, int):
        if a != b:
            problems.append(f"{where}: {a} vs {b}")
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if not (math.isfinite(a) and math.isfinite(b)) or abs(a - b) > rel * max(abs(a), 1e-300):
            problems.append(f"{where}: {a!r} vs {b!r} (relative {abs(a - b) / max(abs(a), 1e-300):.2e})")
    elif a != b:
        problems.append(f"{where}: {a!r} vs {b!r}")


def compare(a, b, rel):
    """(ok, detail)"""
    if a.endswith(".json"):
        problems = []
        compare_numbers(json.load(open(a)), json.load(open(b)), rel, "", problems)
        return not problems, "; ".join(problems[:5]) or "every number equal"
    if a.endswith(".ply"):
        va, ca = read_ply(a)
        vb, cb = read_ply(b)
        if ca != cb:
            return False, f"elements {ca} vs {cb}"
        worst = []
        for p in ("x", "y", "z", "quality"):
            if p not in va and p not in vb:
                continue
            if p not in va or p not in vb:
                return False, f"property {p} in only one file"
            scale = max(abs(x) for x in va[p]) or 1.0
            d = max(abs(x - y) for x, y in zip(va[p], vb[p])) / scale
            worst.append(f"{p} {d:.1e}")
            if not d <= rel:
                return False, f"{p}: max |a - b| / max |a| = {d:.2e} > {rel:g}"
        return True, f"{ca.get('vertex')} vertices, relative differences " + ", ".join(worst)
    if a.endswith(".cfvd"):
        same = open(a, "rb").read() == open(b, "rb").read()
        return same, "byte for byte equal" if same else "bytes differ"
    return False, "unknown kind of file"


def main(argv):
    rel = 1e-6
    if argv[:1] == ["--rel"]:
        rel, argv = float(argv[1]), argv[2:]
    report = Report()
    for pair in argv:
        a, b = pair.split(":", 1)
        try:
            ok, detail = compare(a, b, rel)
        except (OSError, ValueError, KeyError, StopIteration, struct.error) as e:
            ok, detail = False, f"{type(e).__name__}: {e}"
        report.check(ok, f"{b} = {a} to {rel:g}: {detail}")
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
