# SPDX-License-Identifier: GPL-3.0-or-later
"""docs/python.md's examples: the 15-line one runs as written (on a mesh of its name), and the
retrieval one is the code examples/python/retrieval.py runs (tests/python/test_examples.py)."""
import os
import re
import subprocess
import sys

import canonform

SOURCE = os.environ.get("CANONFORM_SOURCE_DIR", ".")


def blocks():
    text = open(os.path.join(SOURCE, "docs", "python.md"), encoding="utf-8").read()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_the_15_line_example_runs_as_written(tmp_path):
    code = blocks()[0]
    assert len(code.strip().splitlines()) <= 15, code
    name = re.search(r'read_mesh\("([^"]+)"\)', code).group(1)
    canonform.write_mesh(tmp_path / name, *canonform.figure(3000, pose=3))
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                       env=dict(os.environ, MPLBACKEND="Agg"))
    assert r.returncode == 0, r.stderr
    iterations, stress = r.stdout.split()
    assert int(iterations) > 0 and float(stress) > 0
    assert (tmp_path / "canonical_form.png").stat().st_size > 10000


def test_the_retrieval_example_is_the_scripts():
    code = next(b for b in blocks() if "canonform.retrieve(" in b).splitlines()
    script = open(os.path.join(SOURCE, "examples", "python", "retrieval.py"), encoding="utf-8").read()
    loop = next(k for k, line in enumerate(code) if line.startswith("for method, r in"))
    for line in code[loop:loop + 3]:  # the loop over the methods' measures
        assert line in script, line
    assert "canonform.retrieve(dataset, " in script and "canonform.evaluate(D, labels)" in script
