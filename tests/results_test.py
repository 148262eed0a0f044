# SPDX-License-Identifier: GPL-3.0-or-later
"""Every result file in bench/results/ is used, and kept once (ctest layout.results).

usage: /usr/bin/python3 tests/results_test.py SOURCE_DIR

- Each file under bench/results/ is referenced by another file of the repository - a docs page,
  the docs generator, a benchmark or experiment script, a test, or another result file's metadata
  (bench/results/manifest.json) - by its path from the repository (bench/results/retrieval/x.json)
  or from bench/results/ (retrieval/x.json, or a bare name for a file directly in it), as a word of
  its own (docs/images/x.png does not name bench/results/x.png). A file nothing names is a
  leftover: delete it (git keeps it), or say where it is used.
- No picture is committed twice: no file of bench/results/ has the bytes of one in docs/images/
  (the benchmarks draw their pictures straight into docs/images/, where the pages take them).
"""
import hashlib
import os
import re
import sys

root = sys.argv[1]
results = os.path.join(root, "bench", "results")
SKIP_DIRS = {".git", "external", "__pycache__", "node_modules", "site"}
TEXT = (".md", ".py", ".sh", ".json", ".jsonl", ".yml", ".yaml", ".txt", ".cmake", ".cpp", ".h", ".csv", ".in")


def files_under(top):
    for d, dirs, files in os.walk(top):
        dirs[:] = [x for x in dirs if x not in SKIP_DIRS and not (d == root and x.startswith("build"))]
        for f in files:
            yield os.path.join(d, f)


# every path-like word of every text file, and the files it occurs in
WORD = re.compile(r"(?<![\w./-])[\w./-]+")
words = {}
for path in files_under(root):
    name = os.path.basename(path)
    if name.endswith(TEXT) or name in ("CMakeLists.txt", "run"):
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue
        for w in set(WORD.findall(text)):
            words.setdefault(w.rstrip("./"), set()).add(path)

problems = []
checked = 0
for path in sorted(files_under(results)):
    checked += 1
    rel_repo = os.path.relpath(path, root).replace(os.sep, "/")
    rel_results = os.path.relpath(path, results).replace(os.sep, "/")
    if not (words.get(rel_repo, set()) | words.get(rel_results, set())) - {path}:
        problems.append(f"{rel_repo}: nothing references it (no page, script, test or manifest names it)")


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


images = os.path.join(root, "docs", "images")
shown = {digest(p): os.path.relpath(p, root) for p in files_under(images)} if os.path.isdir(images) else {}
for path in files_under(results):
    twin = shown.get(digest(path))
    if twin:
        problems.append(f"{os.path.relpath(path, root)}: the same bytes as {twin} (keep one: the benchmark draws into "
                        "docs/images/)")

for p in problems:
    print("results:", p)
print(f"results: {checked} files in bench/results checked; {len(problems)} problems")
sys.exit(1 if problems or not checked else 0)
