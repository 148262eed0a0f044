# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the generated parts of the documentation in docs/, or checks that they are up to date.

usage: /usr/bin/python3 tools/docs/generate.py --params PARAMS.json --canonform CANONFORM [--check] [--root DIR]

PARAMS.json is the output of `canonform_params` (every filter, method and parameter, from the filter
tables and the method registry); CANONFORM is the built tool, whose --help texts make the
command-line reference. A page holds hand-written prose and generated blocks:

    <!-- generated: KIND [ARG ...] -->
    ... (written by this script; do not edit) ...
    <!-- end generated -->

KIND is one of
    version                   the version, from PARAMS.json (CMake's project() version)
    plan                      whole-collection costs at 10^4-10^6 models, from the 600-mesh and query benchmarks
    filter-menu               every filter: menu, name, Python name, what it does
    filters                   every filter of both plugins with every parameter (type, default, range, tooltip)
    pymeshlab                 every filter's Python name and keywords, as pymeshlab calls them
    methods                   the canonical-form methods of the registry and their parameters
    cli-commands              the tool's commands, one line each (canonform --help)
    cli                       `canonform --help` and `canonform COMMAND --help` of every command
    table ID                  a benchmark table of bench/results/manifest.json, with its command and conditions
    record FILE [KEY=VALUE]   a recorded result (bench/results/retrieval/*.json, bench/results/paper/*.json),
                              optionally only its rows whose KEY is VALUE
    figure ID                 a picture of bench/results/manifest.json, with its command and result file
With --check nothing is written: the script lists every page whose generated blocks differ from what
it would write, and exits with 1 if there is one (the test docs.generated).
"""
import argparse
import difflib
import glob
import json
import os
import re
import subprocess
import sys

BLOCK = re.compile(r"(<!-- generated: (?P<args>[^>]*?) -->\n)(?P<body>.*?)(<!-- end generated -->)", re.S)


def md_escape(text):
    """Text for a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def fmt_number(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v == int(v) and abs(v) < 1e15:
            return str(int(v)) if abs(v) >= 1 or v == 0 else repr(v)
        return f"{v:g}"
    return str(v)


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(md_escape(c) for c in r) + " |")
    return "\n".join(out) + "\n"


def html_to_md(info):
    """A filter's MeshLab description (HTML with <br>, <b>, <i>) as Markdown paragraphs."""
    text = info.replace("<br><br>", "\n\n").replace("<br>", "\n")
    text = re.sub(r"</?b>", "**", text)
    text = re.sub(r"</?i>", "*", text)
    return text


def first_sentence(text):
    text = re.sub(r"<[^>]+>", "", text.split("<br>")[0])
    m = re.match(r"(.+?[.:])(\s|$)", text)
    return m.group(1) if m else text


class Generator:
    def __init__(self, root, params, canonform):
        self.root = root
        self.params = params
        self.canonform = canonform
        with open(os.path.join(root, "bench/results/manifest.json")) as f:
            self.manifest = json.load(f)
        self._help = {}
        self.record_page = False  # the page being written is a record (docs/records/)

    # --- filters, pymeshlab, methods ---------------------------------------------------------
    def filters_all(self):
        for plugin in self.params["plugins"]:
            for f in plugin["filters"]:
                yield plugin["plugin"], f

    def param_type(self, p):
        if p["type"] == "enum":
            return "enum: " + ", ".join(f"`{c}`" for c in p["choices"])
        return p["type"]

    def param_range(self, p):
        if p["range"] is None:
            return "-"
        lo, hi = p["range"]
        return f"{fmt_number(lo)} to {fmt_number(hi)}"

    def default_text(self, p):
        if p["type"] == "string":
            return f"`\"{p['default']}\"`" if p["default"] != "" else "`\"\"` (empty)"
        return f"`{fmt_number(p['default'])}`"

    def gen_version(self, args):
        return f"This documentation describes **canonform {self.params['version']}**.\n"

    def gen_filter_menu(self, args):
        rows = []
        for plugin, f in self.filters_all():
            rows.append([f["menu"], f"**{f['name']}**", f"`{f['python_name']}`", first_sentence(f["info"])])
        return table(["menu", "filter", "Python name", "what it does"], rows)

    def gen_filters(self, args):
        out = []
        for plugin, f in self.filters_all():
            out.append(f"## {f['name']}\n")
            out.append(f"*{f['menu']}* · plugin `{plugin}` · Python name `{f['python_name']}` · "
                       f"script `{f['script']}`\n")
            out.append(html_to_md(f["info"]) + "\n")
            rows = []
            for p in f["parameters"]:
                rows.append([f"`{p['name']}`", self.param_type(p), self.default_text(p), self.param_range(p),
                             p["label"], p["tooltip"]])
            out.append(table(["parameter", "type", "default", "range", "dialog label", "tooltip"], rows))
        return "\n".join(out)

    def py_default(self, p):
        d = p["default"]
        if p["type"] == "bool":
            return "True" if d else "False"
        if p["type"] in ("enum", "string"):
            return repr(d)
        if p["type"] == "float":
            return repr(float(d))
        return str(d)

    def py_type(self, p):
        return {"bool": "bool", "int": "int", "float": "float", "string": "str",
                "enum": "str (or its index)"}[p["type"]]

    def gen_pymeshlab(self, args):
        out = []
        for plugin, f in self.filters_all():
            out.append(f"## `{f['python_name']}`\n")
            out.append(f"MeshLab's *{f['name']}* (plugin `lib{plugin}.so`). Every keyword at its default:\n")
            call = ",\n".join(f"    {p['name']}={self.py_default(p)}" for p in f["parameters"])
            out.append(f"```python\nms.apply_filter('{f['python_name']}',\n{call})\n```\n")
            rows = []
            for p in f["parameters"]:
                choices = (" (" + ", ".join(repr(c) for c in p["choices"]) + ")") if p["choices"] else ""
                rows.append([f"`{p['name']}`", self.py_type(p) + choices, f"`{self.py_default(p)}`",
                             self.param_range(p), p["tooltip"]])
            out.append(table(["keyword", "Python type", "default", "range", "meaning"], rows))
        return "\n".join(out)

    def gen_methods(self, args):
        out = []
        rows = [[f"`{m['name']}`", m["filter"] + (f" (`{m['label']}`)" if m["filter"] else "") or "-", m["help"]]
                for m in self.params["methods"]]
        out.append(table(["method", "filter (its enum entry)", "what it is"], [[a, b or "-", c] for a, b, c in rows]))
        for m in self.params["methods"]:
            if not m["parameters"]:
                continue
            out.append(f"\n### `{m['name']}`\n")
            prow = []
            for p in m["parameters"]:
                kind = "one of " + ", ".join(f"`{c}`" for c in p["choices"]) if p["choices"] else (
                    "integer" if p["integer"] else "number")
                rng = "-" if p["range"] is None else f"{fmt_number(p['range'][0])} to {fmt_number(p['range'][1])}"
                opt = f"`--{p['name'].replace('_', '-')}`" + (f", `--{p['alias']}`" if p["alias"] else "")
                prow.append([f"`{p['name']}`", opt, f"`{p['default']}`", kind, rng,
                             "yes" if p["affects_result"] else "no", p["help"]])
            out.append(table(["parameter", "tool option", "default", "value", "range", "in the cache key", "meaning"],
                             prow))
        return "\n".join(out)

    # --- command line ------------------------------------------------------------------------
    def help(self, *command):
        if command not in self._help:
            r = subprocess.run([self.canonform, *command, "--help"], capture_output=True, text=True)
            if r.returncode != 0:
                sys.exit(f"generate.py: `canonform {' '.join(command)} --help` failed: {r.stderr}")
            self._help[command] = r.stdout.rstrip() + "\n"
        return self._help[command]

    def commands(self, *parent):
        """(name, description) of every command (or of PARENT's subcommands), from its --help."""
        parts = re.split(r"^subcommands:\s*$", self.help(*parent), flags=re.M | re.I)
        if len(parts) < 2:
            return []
        part = parts[1]
        out = []
        for line in part.splitlines():
            m = re.match(r"\s{2}(\S+)\s+(.*)", line)
            if m:
                out.append([m.group(1), m.group(2).strip()])
            elif out and line.strip():
                out[-1][1] += " " + line.strip()
        return out

    def gen_cli_commands(self, args):
        return table(["command", "what it does"],
                     [[f"[`{n}`](reference/cli.md#canonform-{n})", d] for n, d in self.commands()])

    def gen_cli(self, args):
        out = ["## canonform\n", "```text\n$ canonform --help\n" + self.help() + "```\n"]
        for name, _ in self.commands():
            out.append(f"## canonform {name}\n")
            out.append(f"```text\n$ canonform {name} --help\n{self.help(name)}```\n")
            for sub, _ in self.commands(name):
                out.append(f"### canonform {name} {sub}\n")
                out.append(f"```text\n$ canonform {name} {sub} --help\n{self.help(name, sub)}```\n")
        return "\n".join(out)

    # --- results -----------------------------------------------------------------------------
    def entry(self, kind, ident):
        try:
            return self.manifest[kind][ident]
        except KeyError:
            sys.exit(f"generate.py: no {kind[:-1]} '{ident}' in bench/results/manifest.json")

    def read(self, path):
        with open(os.path.join(self.root, path)) as f:
            return f.read()

    def jsonl_table(self, path, key, where, columns, group=None):
        lines = [json.loads(x) for x in self.read(path).splitlines() if x.strip()]
        rows = [r for r in lines if key in r and all(str(r.get(k)) == v for k, v in where.items())]
        header = [line for line in lines if key not in line]
        if group:  # one row per value of `group`: the median of each number over its rows
            groups = {}
            for r in rows:
                groups.setdefault(r[group], []).append(r)
            rows = []
            for value, members in groups.items():
                m = {"runs": len(members)}
                for k in members[0]:
                    vals = [x[k] for x in members if k in x]
                    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
                        vals = sorted(vals)
                        mid = len(vals) // 2
                        m[k] = vals[mid] if len(vals) % 2 else (vals[mid - 1] + vals[mid]) / 2
                    else:
                        m[k] = vals[0]
                m[group] = value
                rows.append(m)
        cols = columns or list(dict.fromkeys(k for r in rows for k in r))
        body = [[fmt_number(r[c]) if c in r else "-" for c in cols] for r in rows]
        return table([c.replace("_", " ") for c in cols], body), header

    @staticmethod
    def machine(e, header=()):
        """The machine of a result, from its metadata: "2 cores (AMD EPYC)"; "" when unknown."""
        meta = dict(e.get("machine", {}))
        for h in header:
            meta.update({k: h[k] for k in ("cpus", "cpu") if k in h})
        if "cpus" not in meta:
            return ""
        return f"{meta['cpus']} cores" + (f" ({meta['cpu']})" if meta.get("cpu") else "")

    def conditions_line(self, e, header=()):
        """Command, conditions and result file of a table, in a neutral form: the conditions say how it
        was measured (repeats, medians, pinning) and on how many cores, never when, on which build or
        under what load (those stay in the result file's metadata)."""
        parts = [f"`{e['command']}`"]
        cond = "; ".join(c for c in (e.get("conditions", ""), self.machine(e, header)) if c)
        if self.record_page:  # a record (docs/records/) says when, on which build and under what load
            cond = "; ".join(c for c in [cond, e.get("provenance", "")] + [
                f"{k.replace('_', ' ')} {h[k]}" for h in header for k in ("date", "build", "load_before", "load_after")
                if k in h] if c)
        if cond:
            parts.append(cond)
        files = e.get("files") or [e.get("table") or e.get("jsonl")]
        parts.append("result: " + ", ".join(f"`{f}`" for f in files if f))
        return "*" + " · ".join(parts) + "*\n"

    def gen_table(self, args):
        e = self.entry("tables", args[0])
        if "table" in e:
            body, header = self.read(e["table"]), []
        else:
            body, header = self.jsonl_table(e["jsonl"], e["key"], e.get("where", {}), e.get("columns"), e.get("group"))
        if e.get("summary") == "600":
            body += self.summary_600(e)
        return self.conditions_line(e, header) + "\n" + body

    def summary_600(self, e):
        """The whole 600-mesh run from the stages: per-mesh CPU seconds x 600 plus the rest."""
        st = {}
        for r in (json.loads(x) for x in self.read(e["jsonl"]).splitlines() if x.strip()):
            if "stage" in r and (r["stage"] != "codebook" or r.get("method") == "kmeans"):
                st[r["stage"]] = r
        form, views = st["canonical_form_N"]["median_cpu_s"], st["views_and_sift"]["median_cpu_s"]
        rest = [("codebook (kmeans)", st["codebook"]["cpu_s"]), ("histograms", st["histograms"]["cpu_s"]),
                ("distances", st["distance_matrix"]["cpu_s"])]
        total = 600 * (form + views) + sum(v for _, v in rest)
        parts = " + ".join(f"{v:g} ({k})" for k, v in rest)
        return (f"\n600 meshes: {form:g} + {views:g} CPU s per mesh (form N, views and SIFT) x 600 + {parts} = "
                f"**{total:.0f} CPU s, {total / 2 / 60:.1f} minutes on 2 cores**.\n")

    def gen_record(self, args):
        """A recorded result; KEY=VALUE after the file keeps only the rows with that value (e.g. sift=canonform)."""
        path = args[0]
        rec = json.loads(self.read(path))
        where = dict(a.split("=", 1) for a in args[1:])
        rec["rows"] = [r for r in rec["rows"] if all(str(r.get(k)) == v for k, v in where.items())]
        if not rec["rows"]:
            sys.exit(f"generate.py: {path}: no row with {where}")
        cols = [c for c in rec["columns"] if c["key"] not in where]  # a column of one value says nothing
        best = {}
        for c in cols:
            if c.get("best") in ("max", "min"):
                vals = [r[c["key"]] for r in rec["rows"] if isinstance(r.get(c["key"]), (int, float))]
                if vals:
                    best[c["key"]] = (max if c["best"] == "max" else min)(vals)
        body = []
        for r in rec["rows"]:
            cells = []
            for c in cols:
                v = r.get(c["key"])
                if v is None:
                    cells.append("-")
                    continue
                s = f"{v:.{c['digits']}f}" if "digits" in c and isinstance(v, (int, float)) else fmt_number(v)
                if c["key"] in best and v == best[c["key"]] and len(rec["rows"]) > 1:
                    s = f"**{s}**"
                cells.append(s)
            body.append(cells)
        line = []
        if rec.get("command"):
            line.append(f"`{rec['command']}`")
        if rec.get("conditions"):
            line.append(rec["conditions"])
        if self.record_page and rec.get("provenance"):
            line.append(rec["provenance"])
        line.append(f"result: `{path}`" + (f" ({rec['source']})" if rec.get("source") else ""))
        return "*" + " · ".join(line) + "*\n\n" + table([c["title"] for c in cols], body)

    def gen_figure(self, args):
        e = self.entry("figures", args[0])
        img = e["image"]
        if not os.path.exists(os.path.join(self.root, "docs", img)):
            sys.exit(f"generate.py: figure '{args[0]}': docs/{img} does not exist")
        cap = [e["caption"]] if e.get("caption") else []
        cap.append(f"`{e['command']}`")
        if e.get("files"):
            cap.append("result: " + ", ".join(f"`{f}`" for f in e["files"]))
        # the page's folder decides the relative path of the image
        return f"![{e['alt']}]({{prefix}}{img})\n\n*" + " · ".join(cap) + "*\n"

    def gen_plan(self, args):
        """Whole-collection costs for 10^4, 10^5 and 10^6 models from the 600-mesh and query benchmarks."""
        b600 = [json.loads(x) for x in self.read(self.manifest["tables"]["bench_600"]["jsonl"]).splitlines() if x.strip()]
        bq = [json.loads(x) for x in self.read(self.manifest["tables"]["query"]["jsonl"]).splitlines() if x.strip()]
        st = {}
        for r in b600:
            if "stage" in r and (r["stage"] != "codebook" or r.get("method") == "kmeans"):
                st[r["stage"]] = r
        per_mesh = st["canonical_form_N"]["median_cpu_s"] + st["views_and_sift"]["median_cpu_s"]
        per_hist = st["histograms"]["cpu_s"] / st["histograms"]["models"]
        n = st["distance_matrix"]["models"]
        per_pair = st["distance_matrix"]["cpu_s"] / (n * (n - 1) / 2)
        feature_bytes = st["views_and_sift"]["median_keypoints"] * 128 * 4
        lat = next(r for r in bq if r.get("stage") == "latency")
        per_query_model = lat["exact_median_cpu_s"] / lat["models"]
        idx = next(r for r in bq if r.get("stage") == "index_build")
        index_bytes = (idx["histogram_mib"] + idx["codes_mib"]) * 2 ** 20 / idx["models"]
        code_bytes = idx["codes_mib"] * 2 ** 20 / idx["models"]
        # A two-stage query: the first pass scans every model's code (grows with N), clock matching
        # ranks the default number of candidates (collection_index.h's rule, from params.json).
        # Queries one after another (latency_by_candidates at the default count) if measured, else
        # the alternating figures (each two-stage query after an exhaustive one: cold caches).
        stream = next((r for r in bq if r.get("stage") == "latency_by_candidates"
                       and r["candidates"] == lat["candidates"]), None)
        if stream:
            first = stream["first_pass_median_cpu_s"]
            per_candidate = stream["rerank_cpu_us_per_candidate"] * 1e-6
        else:
            first = lat["first_pass_median_s"]
            per_candidate = max(0.0, lat["two_stage_median_cpu_s"] - first) / lat["candidates"]
        q = self.params["query"]
        rule = q["candidates_rule"]

        def candidates(N, k=10):
            return min(N, max(q["candidates_min"], q["candidates_per_k"] * k, N // q["candidates_share"]))

        def two_stage(N):
            return per_candidate * candidates(N) + first * N / lat["models"]

        def h(x):
            return f"{x:,.0f}" if x >= 100 else f"{x:.2g}" if x >= 0.01 else "< 0.01"

        def size(x):
            for unit, f in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
                if x >= f:
                    return f"{x / f:.3g} {unit}"
            return f"{x / 1e3:.3g} kB"

        sizes = [10 ** 4, 10 ** 5, 10 ** 6]
        rows = [
            ["forms + views + SIFT (CPU-hours)"] + [h(N * per_mesh / 3600) for N in sizes],
            ["histograms (CPU-hours)"] + [h(N * per_hist / 3600) for N in sizes],
            ["N x N distance matrix (CPU-hours)"] + [h(N * (N - 1) / 2 * per_pair / 3600) for N in sizes],
            ["N x N matrix on disk (float32)"] + [size(4 * N * N) for N in sizes],
            ["merge memory (matrix as float, measures in double)"] + [size(12 * N * N) for N in sizes],
            ["instead: every model's top 10 found exhaustively through the index (CPU-hours)"]
            + [h(N * N * per_query_model / 3600) for N in sizes],
            ["default first-pass candidates of a top-10 query"] + [f"{candidates(N):,}" for N in sizes],
            ["or two-stage, the default candidates (CPU-hours)"] + [h(N * two_stage(N) / 3600) for N in sizes],
            ["one exhaustive top-10 query (CPU s)"] + [f"{N * per_query_model:.2g}" for N in sizes],
            ["one two-stage top-10 query (CPU s)"] + [f"{two_stage(N):.2g}" for N in sizes],
            ["index file (mapped by a query; histograms and first-pass codes)"] + [size(N * index_bytes) for N in sizes],
            ["first-pass codes (resident in a query job)"] + [size(N * code_bytes) for N in sizes],
            ["cached SIFT features on disk (deletable once the histograms exist)"]
            + [size(N * feature_bytes) for N in sizes],
        ]
        inputs = (f"*Per mesh {per_mesh:.3f} CPU s (form {st['canonical_form_N']['median_cpu_s']} + views and SIFT "
                  f"{st['views_and_sift']['median_cpu_s']}), histograms {per_hist:.3f} CPU s per mesh, "
                  f"{per_pair * 1e6:.1f} CPU microseconds per distance pair "
                  f"(`{self.manifest['tables']['bench_600']['jsonl']}`); {per_query_model * 1e6:.1f} CPU microseconds "
                  f"per model and exhaustive query, a two-stage query {per_candidate * 1e6:.1f} CPU microseconds of clock "
                  f"matching per candidate ({rule} candidates for N models) plus a first pass of {first:.4f} s per "
                  f"{lat['models']:,} models, {index_bytes / 1e3:.2f} kB of index per model "
                  f"(`{self.manifest['tables']['query']['jsonl']}`).*\n")
        return inputs + "\n" + table(["", "10^4 models", "10^5 models", "10^6 models"], rows)

    # --- pages -------------------------------------------------------------------------------
    def render(self, page, args_text):
        args = args_text.split()
        kind, rest = args[0], args[1:]
        rel = os.path.relpath(page, os.path.join(self.root, "docs"))
        self.record_page = rel.startswith("records" + os.sep)
        fn = getattr(self, "gen_" + kind.replace("-", "_"), None)
        if fn is None:
            sys.exit(f"generate.py: {page}: unknown block kind '{kind}'")
        text = fn(rest)
        depth = os.path.relpath(page, os.path.join(self.root, "docs")).count(os.sep)
        return text.replace("{prefix}", "../" * depth)

    def page(self, path):
        with open(path) as f:
            text = f.read()

        def replace(m):
            return m.group(1) + self.render(path, m.group("args")) + m.group(4)

        return text, BLOCK.sub(replace, text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--params", required=True)
    ap.add_argument("--canonform", required=True)
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    a = ap.parse_args()
    root = os.path.realpath(a.root)
    with open(a.params) as f:
        params = json.load(f)
    gen = Generator(root, params, os.path.realpath(a.canonform))
    stale, blocks = [], 0
    for path in sorted(glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True)):
        old, new = gen.page(path)
        blocks += len(BLOCK.findall(old))
        if old == new:
            continue
        rel = os.path.relpath(path, root)
        if a.check:
            stale.append(rel)
            diff = difflib.unified_diff(old.splitlines(), new.splitlines(), rel, rel + " (generated)", lineterm="", n=1)
            print("\n".join(list(diff)[:40]))
        else:
            with open(path, "w") as f:
                f.write(new)
            print(f"generate.py: wrote {rel}")
    if a.check:
        if stale:
            print(f"generate.py: {len(stale)} page(s) out of date: {', '.join(stale)}\n"
                  "  regenerate: cmake --build BUILD --target docs  (or tools/docs/generate.py, see its --help)")
            sys.exit(1)
        print(f"generate.py: {blocks} generated blocks in docs/ are up to date")


if __name__ == "__main__":
    main()
