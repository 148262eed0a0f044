# SPDX-License-Identifier: GPL-3.0-or-later
"""The documentation's tests (ctest -R docs): one mode per test.

usage: /usr/bin/python3 tests/docs_test.py MODE --source DIR --work DIR [options]

  generated --params CANONFORM_PARAMS --canonform CANONFORM
      every generated block of docs/ is what tools/docs/generate.py writes now from the filter
      tables, the method registry, the tool's --help and bench/results (fails, with the diff and
      the command that regenerates them, when a page is out of date)
  site
      `mkdocs build --strict` into WORK/site (mkdocs.yml, Debian's mkdocs and mkdocs-material), then
      tools/docs/check_site.py: every internal link, anchor and image of the built site resolves
  browser
      tools/docs/browser_check.py on WORK/site (built by `site`): headless Chromium renders the home
      page, the MeshLab filters page, the results page and the filter reference with their images
      and stylesheets; screenshots in WORK/preview
  examples --bin DIR --canonform CANONFORM
      the C++ examples of docs/library.md and README.md's (built into DIR) run on a generated figure
  readme
      README.md: at most 200 lines, no dates, load averages, machine paths or plans, the two commands,
      and every link leads to a file (and heading) of the repository
  pages
      every reference page (docs/ outside docs/records/, CHANGELOG.md which docs/changelog.md includes,
      and mkdocs.yml's navigation) says what the software does, not when or where it was measured:
      no dates (the changelog's release headings excepted), build hashes, issue numbers, load figures
      or machine paths; every record page (docs/records/) is dated and in the navigation
  version --version X.Y.Z --canonform CANONFORM --params CANONFORM_PARAMS
      one version: CMake's project() version, `canonform --version`, the parameter dump the pages are
      generated from, and the newest release of CHANGELOG.md
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

failures = 0


def check(ok, what, detail=""):
    global failures
    print(f"  {'ok  ' if ok else 'FAIL'} {what}" + (f"\n       {detail}" if detail and not ok else ""))
    failures += not ok


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def params_json(a):
    r = run([a.params])
    if r.returncode != 0:
        sys.exit(f"{a.params} failed: {r.stderr}")
    path = os.path.join(a.work, "params.json")
    with open(path, "w") as f:
        f.write(r.stdout)
    return path


def mode_generated(a):
    r = run(["/usr/bin/python3", os.path.join(a.source, "tools/docs/generate.py"), "--check", "--params",
             params_json(a), "--canonform", a.canonform, "--root", a.source])
    print(r.stdout + r.stderr)
    check(r.returncode == 0, "the generated parts of docs/ are up to date",
          "regenerate them: cmake --build BUILD --target docs")


def mode_site(a):
    if shutil.which("mkdocs") is None:
        check(False, "mkdocs is installed", "Debian's mkdocs and mkdocs-material: tools/setup.sh installs them")
        return
    site = os.path.join(a.work, "site")
    # snippets (--8<--) are relative to the repository's root: run there
    r = run(["mkdocs", "build", "--strict", "--clean", "--config-file", os.path.join(a.source, "mkdocs.yml"),
             "--site-dir", site], cwd=a.source)
    warnings = [line for line in r.stderr.splitlines() if "WARNING" in line or "ERROR" in line]
    check(r.returncode == 0 and not warnings, "mkdocs build --strict: no warning",
          "\n       ".join(warnings or r.stderr.splitlines()[-10:]))
    if r.returncode != 0:
        return
    r = run(["/usr/bin/python3", os.path.join(a.source, "tools/docs/check_site.py"), site])
    print(r.stdout)
    check(r.returncode == 0, "every internal link, anchor and image of the site resolves")
    with open(os.path.join(a.source, "mkdocs.yml")) as f:
        nav = re.findall(r":\s+(\S+\.md)\s*$", f.read(), re.M)
    missing = [p for p in nav if not os.path.isfile(os.path.join(site, p[:-3] + ".html"))]
    check(not missing and len(nav) > 20, f"every page of the navigation was built ({len(nav)})", str(missing))
    with open(os.path.join(site, "index.html")) as f:
        home = f.read()
    check("fonts.googleapis" not in home and "fonts.gstatic" not in home, "the site loads no web fonts (works offline)")


def mode_browser(a):
    if shutil.which("chromium") is None:
        check(False, "chromium is installed", "Debian's chromium: tools/setup.sh installs it")
        return
    site = os.path.join(a.work, "site")
    if not os.path.isfile(os.path.join(site, "index.html")):
        check(False, f"the site was built ({site}: the test docs.site builds it)")
        return
    r = run(["/usr/bin/python3", os.path.join(a.source, "tools/docs/browser_check.py"), site,
             os.path.join(a.work, "preview")], timeout=300)
    print(r.stdout + r.stderr)
    check(r.returncode == 0, "headless Chromium renders the pages with their images and stylesheets")


def mode_examples(a):
    work = os.path.join(a.work, "examples")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    r = run([a.canonform, "generate", "figure.ply", "--vertices", "2500", "--pose", "4"], cwd=work)
    check(r.returncode == 0, "canonform generate figure.ply", r.stderr)
    ex = lambda name: os.path.join(a.bin, name)  # noqa: E731
    r = run([ex("example_canonical_form"), "figure.ply", "canonical.ply"], cwd=work)
    check(r.returncode == 0 and re.match(r"\d+ feature points, \d+ SMACOF iterations", r.stdout)
          and os.path.getsize(os.path.join(work, "canonical.ply")) > 50000,
          f"examples/cpp/canonical_form.cpp: {r.stdout.strip()}", r.stderr)
    r = run([ex("example_canonical_form"), "missing.off", "x.ply"], cwd=work)
    check(r.returncode == 1 and "bad input" in r.stderr and "missing.off" in r.stderr,
          f"examples/cpp/canonical_form.cpp names a missing file: {r.stderr.strip()}")
    r = run([ex("example_method_by_name"), "figure.ply", "form.ply", "euclidean-N:beta=65"], cwd=work)
    check(r.returncode == 0 and r.stdout.startswith("euclidean-N:beta=65: ") and "final_stress" in r.stdout,
          f"examples/cpp/method_by_name.cpp: {r.stdout.splitlines()[0] if r.stdout else ''}", r.stderr)
    r = run([ex("example_method_by_name"), "figure.ply", "form.ply", "euclidean-N:beta=-1"], cwd=work)
    check(r.returncode == 1 and "beta" in r.stderr,
          f"examples/cpp/method_by_name.cpp refuses a bad parameter: {r.stderr.strip()}")
    r = run([ex("example_retrieval")], cwd=work, timeout=600)
    m = re.match(r"NN ([\d.]+), first tier ([\d.]+), second tier ([\d.]+), E ([\d.]+), DCG ([\d.]+)", r.stdout)
    check(r.returncode == 0 and m is not None and all(0 <= float(x) <= 1 for x in m.groups()),
          f"examples/cpp/retrieval.cpp: {r.stdout.strip()}", r.stderr)
    r = run([ex("example_readme")], cwd=work)
    check(r.returncode == 0 and os.path.getsize(os.path.join(work, "canonical.ply")) > 50000,
          "README.md's C++ quick start (compiled as example_readme) writes canonical.ply", r.stderr)


def slug(heading):
    """The anchor MkDocs (and GitHub) give a heading."""
    h = re.sub(r"[`*_]", "", heading.strip().lower())
    h = re.sub(r"[^\w\- ]", "", h)
    return re.sub(r"\s+", "-", h)


# What makes a line a lab notebook's rather than a reference page's (mode pages; README.md too).
NOTEBOOK = [
    ("a date", re.compile(r"\b20\d\d-[01]\d(-[0-3]\d)?\b|\b(January|February|March|April|May|June|July|August|"
                          r"September|October|November|December) (\d{1,2}, )?20\d\d\b")),
    # a hexadecimal word of 7-40 digits with a letter and a digit, or any after commit/build/branch
    ("a build hash", re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b|"
                                r"\b(commit|build|revision|branch|main)('s)?\s+`?[0-9a-f]{7,40}\b", re.I)),
    ("an issue number", re.compile(r"\b(issue|pull request|PR)s?\s*#?\d+|(^|\s)#\d+\b", re.I)),
    ("a load figure", re.compile(r"\bload( average)?s?( of)?\s*[(:=]?\s*\d|load average|\bquiet machine|"
                                 r"shared machine|machine shared|nothing else running|other jobs", re.I)),
    ("a machine path", re.compile(r"(^|[\s`'\"(=])/(work|root|home/\w+|tmp/data|mnt/data)/")),
]
RELEASE_HEADING = re.compile(r"^## \[?\d+\.\d+\.\d+\]?\s+-\s+20\d\d-\d\d-\d\d\s*$")


def notebook(text, changelog=False):
    """(line number, what, line) of every line that dates, places or loads a figure."""
    found = []
    for n, line in enumerate(text.splitlines(), 1):
        for what, rx in NOTEBOOK:
            if changelog and what == "a date" and RELEASE_HEADING.match(line):
                continue
            if rx.search(line):
                found.append((n, what, line))
    return found


def reference_pages(source):
    """(path relative to SOURCE, is the changelog) of every page the reference lint reads."""
    pages = []
    docs = os.path.join(source, "docs")
    for d, dirs, files in os.walk(docs):
        rel = os.path.relpath(d, source)
        if rel == os.path.join("docs", "records") or rel.startswith(os.path.join("docs", "records") + os.sep):
            dirs[:] = []
            continue
        pages += [(os.path.join(rel, f), f == "changelog.md") for f in sorted(files) if f.endswith(".md")]
    return sorted(pages) + [("CHANGELOG.md", True), ("mkdocs.yml", False)]


def mode_pages(a):
    bad = []
    pages = reference_pages(a.source)
    for rel, changelog in pages:
        path = os.path.join(a.source, rel)
        if not os.path.isfile(path):
            continue
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if rel == "mkdocs.yml":  # the navigation's titles and pages (records' titles are dated there)
            text = "\n".join(line for line in text.splitlines() if "records/" not in line)
        bad += [f"{rel}:{n}: {what}: {line.strip()[:100]}" for n, what, line in notebook(text, changelog)]
    check(not bad, f"{len(pages)} reference pages have no dates, build hashes, issue numbers, load figures or "
          "machine paths (studies go to docs/records/)", "\n       ".join(bad))
    records = os.path.join(a.source, "docs", "records")
    undated, nav = [], ""
    if os.path.isfile(os.path.join(a.source, "mkdocs.yml")):
        with open(os.path.join(a.source, "mkdocs.yml"), encoding="utf-8") as f:
            nav = f.read()
    names = sorted(f for f in os.listdir(records) if f.endswith(".md")) if os.path.isdir(records) else []
    for name in names:
        with open(os.path.join(records, name), encoding="utf-8") as f:
            head = f.read(600)
        if name != "index.md" and not re.search(r"\b20\d\d-\d\d-\d\d\b", head):
            undated.append(f"docs/records/{name}: no date (YYYY-MM-DD) in its title or first lines")
        if "records/" + name not in nav:
            undated.append(f"docs/records/{name}: not in mkdocs.yml's navigation")
    check(not undated, f"{len(names)} record pages are dated and in the navigation", "\n       ".join(undated))


def mode_readme(a):
    path = os.path.join(a.source, "README.md")
    with open(path) as f:
        text = f.read()
    lines = text.splitlines()
    check(len(lines) <= 200, f"README.md has at most 200 lines ({len(lines)})")
    found = [(k + 1, line) for k, line in enumerate(lines)
             if re.search(r"this machine|not built|\bplan(ned)?\b|TODO", line, re.I)]
    found += [(n, line) for n, _, line in notebook(text)]
    check(not found, "README.md has no dates, build hashes, issue numbers, load figures, machine paths or plans",
          "; ".join(f"line {n}: {line.strip()[:80]}" for n, line in sorted(found)))
    for cmd in ("tools/run_example.sh", "tools/run_tests.sh"):
        check(re.search(r"^" + re.escape(cmd) + r"\s+# \d\. ", text, re.M) is not None, f"README.md gives command {cmd}")
    bad = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue
        file, _, anchor = target.partition("#")
        full = os.path.join(a.source, file)
        if not os.path.exists(full):
            bad.append(f"{target}: no such file")
        elif anchor and file.endswith(".md"):
            with open(full) as f:
                anchors = {slug(h) for h in re.findall(r"^#+ (.+)$", f.read(), re.M)}
            if anchor not in anchors:
                bad.append(f"{target}: no heading '#{anchor}' in {file}")
    check(not bad, "every link of README.md leads to a file (and heading) of the repository", "; ".join(bad))


def mode_version(a):
    r = run([a.canonform, "--version"])
    check(r.returncode == 0 and r.stdout.strip() == f"canonform {a.version}",
          f"canonform --version prints 'canonform {a.version}' (CMake's project() version): {r.stdout.strip()!r}")
    with open(params_json(a)) as f:
        check(json.load(f)["version"] == a.version, "the documentation is generated for that version")
    with open(os.path.join(a.source, "CHANGELOG.md")) as f:
        releases = re.findall(r"^## \[?(\d+\.\d+\.\d+)", f.read(), re.M)
    check(releases[:1] == [a.version], f"CHANGELOG.md's newest release is {a.version}: {releases[:1]}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=["generated", "site", "browser", "examples", "version", "readme", "pages"])
    ap.add_argument("--source", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--params")
    ap.add_argument("--canonform")
    ap.add_argument("--bin")
    ap.add_argument("--version")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    print(f"docs {a.mode}")
    globals()["mode_" + a.mode](a)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
