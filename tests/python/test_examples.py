# SPDX-License-Identifier: GPL-3.0-or-later
"""The scripts of examples/python/ run as a user runs them (docs/python.md shows their lines)."""
import glob
import os
import subprocess
import sys

import pytest

EXAMPLES = sorted(glob.glob(os.path.join(os.environ.get("CANONFORM_SOURCE_DIR", "."), "examples", "python", "*.py")))


def test_there_are_examples():
    assert len(EXAMPLES) >= 2, EXAMPLES


def test_canonical_form_example(tmp_path):
    script = next(e for e in EXAMPLES if e.endswith("canonical_form.py"))
    r = subprocess.run([sys.executable, script], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "SMACOF iterations" in r.stdout
    assert (tmp_path / "canonical_form.png").stat().st_size > 10000


def test_retrieval_example(tmp_path):
    script = next(e for e in EXAMPLES if e.endswith("retrieval.py"))
    r = subprocess.run([sys.executable, script, str(tmp_path / "out")], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "euclidean-N  NN" in r.stdout and (tmp_path / "out" / "run" / "report.md").is_file()
