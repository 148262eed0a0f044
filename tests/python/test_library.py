# SPDX-License-Identifier: GPL-3.0-or-later
"""How the package finds its shared library (canonform/_library.py): by name per platform, in a
fixed order, and a clear error when it is missing or from another build."""
import os
import subprocess
import sys

import pytest

import canonform
from canonform import _library


@pytest.mark.parametrize("platform, name", [
    ("linux", "libcanonform.so"), ("freebsd13", "libcanonform.so"), ("win32", "canonform.dll"),
    ("cygwin", "canonform.dll"), ("darwin", "libcanonform.dylib"),
])
def test_the_library_name_of_each_platform(platform, name):
    assert _library.library_name(platform) == name


def test_candidates_in_order():
    pkg = os.path.join("site", "canonform")
    assert _library.candidates(pkg, "linux", {}) == [os.path.join(pkg, "lib", "libcanonform.so")]
    assert _library.candidates(pkg, "win32", {"CANONFORM_LIBRARY": r"C:\x\canonform.dll"}) == [
        r"C:\x\canonform.dll", os.path.join(pkg, "lib", "canonform.dll")]


def run(code, **env):
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=dict(os.environ, **env))


def test_the_library_loads_on_the_first_call_not_at_import():
    r = run("import sys, canonform; from canonform import _library; print(_library._lib is None, 'numpy' in sys.modules); "
            "canonform.sift_backends(); print(_library._lib is not None)")
    assert r.returncode == 0 and r.stdout.split() == ["True", "False", "True"], r.stdout + r.stderr


def test_a_missing_or_wrong_library_is_a_clear_import_error(tmp_path):
    # CANONFORM_LIBRARY naming no file: the package's own copy, the next candidate, is loaded
    r = run("import canonform; canonform.figure(500)", CANONFORM_LIBRARY=str(tmp_path / "nothing.so"))
    assert r.returncode == 0, r.stderr
    here = os.path.dirname(canonform.__file__)
    # a package whose only candidate is not a library: ImportError naming what was tried
    fake = tmp_path / "pkg"
    (fake / "canonform").mkdir(parents=True)
    for f in os.listdir(here):
        if f.endswith(".py"):
            (fake / "canonform" / f).write_bytes(open(os.path.join(here, f), "rb").read())
    (fake / "canonform" / "lib").mkdir()
    (fake / "canonform" / "lib" / _library.library_name()).write_bytes(b"not a library")
    r = run("import canonform; canonform.figure(500)", PYTHONPATH=str(fake))
    assert r.returncode != 0 and "ImportError" in r.stderr and _library.library_name() in r.stderr, r.stderr


def test_version_and_api_version_agree():
    lib = _library.load()
    assert lib.canonform_version().decode() == canonform.__version__
    assert lib.canonform_api_version() == _library.API_VERSION
