# SPDX-License-Identifier: GPL-3.0-or-later
"""Fixtures of the Python module's tests (tests/python/run_tests.sh runs them against the wheel
installed in a fresh venv, from outside the source tree).

Environment: CANONFORM_TOOL, the `canonform` tool of the same build (the tests compare the module
with it); CANONFORM_SOURCE_DIR, the repository (to check the module does not come from it).
"""
import os
import subprocess

import numpy as np
import pytest

import canonform


@pytest.fixture(scope="session")
def tool():
    path = os.environ.get("CANONFORM_TOOL")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("CANONFORM_TOOL must name the canonform tool of this build (tests/python/run_tests.sh sets it)")
    return path


@pytest.fixture(scope="session")
def run_tool(tool):
    """run_tool(*args, cwd=...) -> stdout; fails the test with the tool's stderr on a non-zero exit."""
    def run(*args, cwd=None):
        r = subprocess.run([tool, *map(str, args)], cwd=cwd, capture_output=True, text=True)
        if r.returncode != 0:
            pytest.fail(f"canonform {' '.join(map(str, args))}: exit {r.returncode}\n{r.stderr}")
        return r.stdout
    return run


@pytest.fixture(scope="session")
def figure_file(tmp_path_factory, run_tool):
    """A 1000-vertex procedural figure written by `canonform generate` (PLY, float32-rounded)."""
    path = tmp_path_factory.mktemp("figure") / "fig.ply"
    run_tool("generate", path, "--vertices", 1000, "--pose", 2)
    return path


@pytest.fixture(scope="session")
def mesh(figure_file):
    return canonform.read_mesh(figure_file)


def aligned_rms(a, b, mirror=True):
    """RMS distance between point sets a and b (n x 3) after the best rigid motion of a onto b
    (and mirror image, if `mirror`): MDS fixes a form only up to these."""
    a = a - a.mean(axis=0)
    b = b - b.mean(axis=0)
    best = np.inf
    for flip in ([1.0, -1.0] if mirror else [1.0]):
        x = a * np.array([flip, 1.0, 1.0])
        u, _, vt = np.linalg.svd(x.T @ b)
        d = np.sign(np.linalg.det(u @ vt))
        r = u @ np.diag([1.0, 1.0, d]) @ vt
        best = min(best, float(np.sqrt(np.mean(np.sum((x @ r - b) ** 2, axis=1)))))
    return best
