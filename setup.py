# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the canonform wheel from source: setuptools (Debian's python3-setuptools) driving the
CMake build.

    pip install --no-build-isolation --no-index .        # docs/python.md

The package is pure Python over the library's C API (ctypes): the CMake target canonform_python
(python/CMakeLists.txt) assembles it - the modules, _version.py, the stubs and lib/libcanonform.so -
in an existing build folder when CANONFORM_PYTHON_BUILD_DIR names one (nothing is compiled twice:
the tests and CI build the wheel this way) or when the repository's build/ (tools/build.sh) has
the package, else in build/pip/, configured with only the library and the package. The wheel is
tagged py3-none-PLATFORM: any Python 3, this platform's library (linked against this system's
libraries; the portable wheel is tools/package.sh --wheel's). Setuptools' own working files go
under that build folder too, never into the source tree.
"""
import os
import re
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py

try:  # setuptools 70 and later
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # Debian bookworm: the wheel package's
    from wheel.bdist_wheel import bdist_wheel

HERE = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(canonform VERSION ([0-9.]+)", f.read()).group(1)


def has_package(build):
    """True if the CMake build in `build` makes the Python package."""
    try:
        with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
            return re.search(r"^CANONFORM_PYTHON:BOOL=ON$", f.read(), re.M) is not None
    except OSError:
        return False


def cmake_build_dir():
    """CANONFORM_PYTHON_BUILD_DIR; else the repository's build/ (tools/build.sh) when it makes the
    package; else build/pip/, a build of the library and the package alone."""
    given = os.environ.get("CANONFORM_PYTHON_BUILD_DIR")
    if given:
        return os.path.abspath(given)
    if has_package(os.path.join(HERE, "build")):
        return os.path.join(HERE, "build")
    return os.path.join(HERE, "build", "pip")


class CMakeBuildPy(build_py):
    """Builds the CMake target canonform_python and copies the package it assembled."""

    def run(self):
        build = cmake_build_dir()
        if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            if os.environ.get("CANONFORM_PYTHON_BUILD_DIR"):
                sys.exit(f"CANONFORM_PYTHON_BUILD_DIR={build} is not a configured CMake build")
            subprocess.check_call([
                "cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                "-DCANONFORM_BUILD_PLUGINS=OFF", "-DCANONFORM_BUILD_TOOLS=OFF", "-DCANONFORM_BUILD_TESTS=OFF",
                "-DCANONFORM_BUILD_BENCH=OFF", "-DCANONFORM_PYTHON=ON"])
        subprocess.check_call(["cmake", "--build", build, "--target", "canonform_python", "-j", str(os.cpu_count() or 1)])
        package = os.path.join(build, "python", "canonform")
        target = os.path.join(self.build_lib, "canonform")
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(package, target, ignore=shutil.ignore_patterns("__pycache__"))


class PlatformWheel(bdist_wheel):
    """py3-none-PLATFORM: any Python 3 (no extension module), this platform's shared library."""

    def finalize_options(self):
        super().finalize_options()
        self.root_is_pure = False

    def get_tag(self):
        return ("py3", "none", super().get_tag()[2])


work = os.path.join(cmake_build_dir(), "setuptools")
os.makedirs(work, exist_ok=True)
setup(
    version=version(),
    packages=["canonform"],
    package_dir={"": "python"},
    cmdclass={"build_py": CMakeBuildPy, "bdist_wheel": PlatformWheel},
    zip_safe=False,
    options={"build": {"build_base": work}, "egg_info": {"egg_base": work}},
)
