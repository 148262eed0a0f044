# SPDX-License-Identifier: GPL-3.0-or-later
"""The reference-page lint of tests/docs_test.py (mode pages) on a small fixture: the pages of
tests/docs_lint/bad/ (a date, build hashes, issue numbers, load figures and a machine path in a page,
a dated changelog entry that is not a release heading, a date in the navigation, an undated record
missing from the navigation) must each be rejected, line by line, and those of tests/docs_lint/good/
(large decimal numbers, a software path, a release date, a dated and listed record that names builds
and loads) accepted.

usage: /usr/bin/python3 tests/docs_lint_test.py SOURCE_DIR WORK_DIR
"""
import os
import re
import subprocess
import sys

source, work = sys.argv[1], sys.argv[2]
lint = [sys.executable, os.path.join(source, "tests", "docs_test.py"), "pages", "--work", work, "--source"]
fixture = os.path.join(source, "tests", "docs_lint")
failures = 0


def check(ok, what, detail=""):
    global failures
    print(f"  {'ok  ' if ok else 'FAIL'} {what}" + (f"\n       {detail}" if detail and not ok else ""))
    failures += not ok


bad = subprocess.run(lint + [os.path.join(fixture, "bad")], capture_output=True, text=True)
found = set(re.findall(r"^\s+(\S+:\d+): (a date|a build hash|an issue number|a load figure|a machine path):",
                       bad.stdout, re.M))
expected = {
    ("docs/page.md:3", "a date"), ("docs/page.md:3", "a build hash"), ("docs/page.md:3", "a load figure"),
    ("docs/page.md:4", "a build hash"), ("docs/page.md:4", "an issue number"),
    ("docs/page.md:5", "a load figure"), ("docs/page.md:5", "a machine path"),
    ("docs/page.md:6", "a date"), ("docs/page.md:6", "a load figure"),
    ("CHANGELOG.md:5", "a date"), ("CHANGELOG.md:5", "a build hash"),
    ("mkdocs.yml:4", "a date"),
}
check(bad.returncode == 1, "the bad fixture is rejected", bad.stdout + bad.stderr)
check(found == expected, f"each of its {len(expected)} faults is named with its line",
      f"missed {sorted(expected - found)}; wrongly named {sorted(found - expected)}")
check("docs/records/study.md: no date" in bad.stdout and "study.md: not in mkdocs.yml" in bad.stdout,
      "an undated record page, missing from the navigation, is rejected")
check("CHANGELOG.md:3" not in bad.stdout, "the changelog's release heading keeps its date")
good = subprocess.run(lint + [os.path.join(fixture, "good")], capture_output=True, text=True)
check(good.returncode == 0, "the good fixture is accepted", good.stdout + good.stderr)
sys.exit(1 if failures else 0)
