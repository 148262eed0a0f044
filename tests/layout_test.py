# SPDX-License-Identifier: GPL-3.0-or-later
"""The library's layout rules, checked on the sources and the built plugins.

usage: /usr/bin/python3 tests/layout_test.py SOURCE_DIR [PLUGIN.so ...]

- an area of src/canonform/ includes only the areas below it (no import circles);
- every namespace an area's file opens is canonform::AREA (common: canonform), nested ones
  (detail, anonymous) inside it; the plugin folders' code is in canonform::meshlab;
- a plugin folder includes nothing from the other plugin folder, and its CMakeLists.txt names no
  file of it;
- a plugin (.so) contains no code of the procedural-mesh library (test and example data only);
- the view-descriptor plugin needs no OpenCV, VLFeat, FAISS, BLAS, LAPACK, OpenMP or oneTBB at run
  time (its SIFT and word assignment are the library's own; those libraries are the tool's);
- one home per kind of file: the programs users run are in apps/ (a C++ file with main() lives in
  apps/, bench/, examples/ or tests/, or is one of the build's generators in tools/); tools/ holds
  build, package, root-filesystem, test and documentation scripts, no analysis script (one that runs
  `canonform retrieve`, reads a run's measures or distances, or plots them: those are in
  experiments/); every script in experiments/ has its ctest experiments.NAME; git tracks no Python
  byte code (.pyc, __pycache__/).
"""
import os
import re
import subprocess
import sys

ALLOWED = {
    "common": set(),
    "numerics": {"common"},
    "surface": {"common", "numerics"},
    "canonical": {"common", "numerics", "surface"},
    "views": {"common", "numerics", "surface", "io"},
    "io": {"common"},
    "retrieval": {"common", "numerics", "surface", "canonical", "views", "io"},
    "procedural": {"common", "numerics", "surface"},
    "meshlab": {"common"},
    # the C API over the whole library (its own headers: canonform.h, the plain C interface)
    "c_api": {"common", "numerics", "surface", "canonical", "views", "io", "retrieval", "procedural"},
}
PLUGINS = ["filter_canonical", "filter_viewdescriptor"]
INCLUDE = re.compile(r'#include\s+"([^"]+)"')
NAMESPACE = re.compile(r"^namespace\s+([\w:]+)\s*\{", re.M)  # at the start of a line: top level


def check_namespaces(rel, text, expected):
    found = NAMESPACE.findall(text)
    for ns in found:
        if ns.startswith("canonform") and ns != expected or not ns.startswith("canonform") and expected not in found:
            problems.append(f"{rel}: opens namespace {ns}, not {expected}")

root = sys.argv[1]
problems = []
lib = os.path.join(root, "src", "canonform")
areas = sorted(d for d in os.listdir(lib) if os.path.isdir(os.path.join(lib, d)))
for area in areas:
    if area not in ALLOWED:
        problems.append(f"src/canonform/{area}: an area without a rule in tests/layout_test.py")
        continue
    for name in sorted(os.listdir(os.path.join(lib, area))):
        path = os.path.join(lib, area, name)
        check_namespaces(f"src/canonform/{area}/{name}", open(path, encoding="utf-8").read(),
                         "canonform" if area == "common" else "canonform::" + area)
        for inc in INCLUDE.findall(open(path, encoding="utf-8").read()):
            m = re.match(r"canonform/([a-z_]+)/", inc)
            if not m:
                problems.append(f"src/canonform/{area}/{name}: includes \"{inc}\" outside the include root")
            elif m.group(1) != area and m.group(1) not in ALLOWED[area]:
                problems.append(f"src/canonform/{area}/{name}: {area} may not include {m.group(1)} (\"{inc}\")")

for plugin in PLUGINS:
    others = [p for p in PLUGINS if p != plugin]
    folder = os.path.join(root, plugin)
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if not os.path.isfile(path):
            continue
        text = open(path, encoding="utf-8").read()
        if name.endswith((".h", ".cpp")):
            check_namespaces(f"{plugin}/{name}", text, "canonform::meshlab")
        for other in others:
            if other + "/" in text or "../" + other in text:
                problems.append(f"{plugin}/{name}: refers to {other}/")
        if name.endswith((".h", ".cpp")):
            for inc in INCLUDE.findall(text):
                # a plugin class's .cpp includes the moc output of its own header (Qt's AUTOMOC
                # makes it: cmake/MeshLabPlugin.cmake, PLUGIN_CLASS)
                own_moc = name.endswith(".cpp") and inc == "moc_" + name and os.path.exists(
                    os.path.join(folder, name[:-4] + ".h"))
                if not own_moc and not inc.startswith("canonform/") and not os.path.exists(os.path.join(folder, inc)):
                    problems.append(f"{plugin}/{name}: includes \"{inc}\" from outside its folder and the library")

for so in sys.argv[2:]:
    symbols = subprocess.run(["nm", "-C", "--defined-only", so], capture_output=True, text=True, check=True).stdout
    leaked = [line for line in symbols.splitlines() if "make_figure" in line or "make_icosphere" in line]
    if leaked:
        problems.append(f"{so}: contains procedural-mesh code ({leaked[0].split()[-1]} ...)")

VIEW_PLUGIN_MAY_NOT_NEED = re.compile(r"libopencv|libvl\.|libfaiss|libblas|libopenblas|liblapack|libgomp|libtbb")
for so in sys.argv[2:]:
    if "filter_viewdescriptor" not in os.path.basename(so):
        continue
    dynamic = subprocess.run(["objdump", "-p", so], capture_output=True, text=True, check=True).stdout
    needed = [line.split()[-1] for line in dynamic.splitlines() if line.strip().startswith("NEEDED")]
    extra = [n for n in needed if VIEW_PLUGIN_MAY_NOT_NEED.match(n)]
    if extra:
        problems.append(f"{so}: needs {', '.join(extra)} (the view filter must not; see src/CMakeLists.txt)")

# --- one home per kind of file -------------------------------------------------------------------
GENERATORS = {"tools/make_mlx.cpp", "tools/docs/params.cpp"}  # programs the build runs to write files
PROGRAM_HOMES = ("apps/", "bench/", "examples/", "tests/")
MAIN = re.compile(r"^\s*int\s+main\s*\(", re.M)
ANALYSIS = re.compile(r"^\s*(import|from)\s+(numpy|matplotlib)\b|metrics\.json|distances\.(bin|csv)|pr\.csv|"
                      r"(\$cf|\$CANONFORM|canonform)\"?\s+retrieve\b", re.M)


def tracked(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True, text=True, check=True).stdout
        return [f for f in out.split("\0") if f]
    except (subprocess.CalledProcessError, FileNotFoundError):  # not a git checkout: every file
        return [os.path.relpath(os.path.join(d, f), root).replace(os.sep, "/") for d, dirs, fs in os.walk(root)
                for f in fs if not d.startswith(os.path.join(root, "build"))]


files = [f for f in tracked(root) if not f.startswith("external/") and os.path.isfile(os.path.join(root, f))]
for f in files:
    if f.endswith(".pyc") or "/__pycache__/" in "/" + f:
        problems.append(f"{f}: Python byte code is tracked (git rm --cached it; .gitignore has __pycache__/)")
    if f.endswith((".cpp", ".cc")) and not f.startswith(PROGRAM_HOMES) and f not in GENERATORS:
        if MAIN.search(open(os.path.join(root, f), encoding="utf-8", errors="replace").read()):
            problems.append(f"{f}: a program outside apps/ (programs users run), bench/, examples/ and tests/")
    if f.startswith("tools/") and not f.startswith("tools/docs/") and f.endswith((".py", ".sh")):
        if ANALYSIS.search(open(os.path.join(root, f), encoding="utf-8", errors="replace").read()):
            problems.append(f"{f}: an analysis script in tools/ (it runs retrieve or reads or plots a run's results): "
                            "it goes to experiments/, with a test")
cmake_tests = open(os.path.join(root, "tests", "CMakeLists.txt"), encoding="utf-8").read()
experiments = [f for f in files if f.startswith("experiments/") and f.endswith((".py", ".sh"))]
for f in experiments:
    name = os.path.splitext(os.path.basename(f))[0]
    if not re.search(r"\bexperiments\." + re.escape(name) + r"\b", cmake_tests) and \
            not re.search(r"\b_experiments\b[^)]*\b" + re.escape(name) + r"\b", cmake_tests):
        problems.append(f"{f}: no test experiments.{name} in tests/CMakeLists.txt (each script has a smoke test)")

for p in problems:
    print("layout:", p)
print(f"layout: {len(areas)} areas, {len(PLUGINS)} plugin folders, {len(sys.argv) - 2} plugins, {len(files)} files "
      f"({len(experiments)} experiment scripts) checked; {len(problems)} problems")
sys.exit(1 if problems else 0)
