# SPDX-License-Identifier: GPL-3.0-or-later
"""Builds the canonform wheel: setuptools (Debian's python3-setuptools) driving the CMake build.

    pip install --no-build-isolation --no-index .        # docs/python.md

The extension and its stubs come from the CMake target canonform_python (python/CMakeLists.txt),
built in an existing build folder when CANONFORM_PYTHON_BUILD_DIR names one (nothing is compiled
twice: the tests and CI build the wheel this way) or when the repository's build/ (tools/build.sh)
makes the module for this Python, else in build/pip/, configured with only the library and the
module. The rest of the package is python/canonform/. Setuptools'
own working files go under that build folder too, never into the source tree.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(canonform VERSION ([0-9.]+)", f.read()).group(1)


def same_python(build):
    """True if the CMake build in `build` makes the module for this interpreter (a venv's counts as
    the interpreter it was made from)."""
    try:
        with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
            cache = dict(re.findall(r"^([A-Za-z_]+):[A-Z]+=(.*)$", f.read(), re.M))
    except OSError:
        return False
    exe = cache.get("Python_EXECUTABLE") or cache.get("_Python_EXECUTABLE")
    ours = getattr(sys, "_base_executable", sys.executable)
    return cache.get("CANONFORM_PYTHON") == "ON" and bool(exe) and os.path.realpath(exe) == os.path.realpath(ours)


def cmake_build_dir():
    """CANONFORM_PYTHON_BUILD_DIR; else the repository's build/ (tools/build.sh) when it makes the
    module for this Python; else build/pip/, a build of the library and the module alone."""
    given = os.environ.get("CANONFORM_PYTHON_BUILD_DIR")
    if given:
        return os.path.abspath(given)
    if same_python(os.path.join(HERE, "build")):
        return os.path.join(HERE, "build")
    return os.path.join(HERE, "build", "pip")


class CMakeBuild(build_ext):
    """Builds the CMake target canonform_python and copies the extension and stubs in."""

    def build_extension(self, ext):
        build = cmake_build_dir()
        jobs = str(os.cpu_count() or 1)
        if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            if os.environ.get("CANONFORM_PYTHON_BUILD_DIR"):
                sys.exit(f"CANONFORM_PYTHON_BUILD_DIR={build} is not a configured CMake build")
            subprocess.check_call([
                "cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                "-DCANONFORM_BUILD_PLUGINS=OFF", "-DCANONFORM_BUILD_TOOLS=OFF", "-DCANONFORM_BUILD_TESTS=OFF",
                "-DCANONFORM_BUILD_BENCH=OFF", "-DCANONFORM_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", build, "--target", "canonform_python", "-j", jobs])
        package = os.path.join(build, "python", "canonform")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = os.path.join(package, "_canonform" + suffix)
        if not os.path.isfile(built):
            found = [f for f in os.listdir(package) if f.startswith("_canonform.")]
            sys.exit(f"{build} has {found or 'no extension'}, not _canonform{suffix} for {sys.executable}: "
                     "configure that build with -DPython_EXECUTABLE=" + sys.executable)
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)
        shutil.copyfile(os.path.join(package, "__init__.pyi"), os.path.join(os.path.dirname(target), "__init__.pyi"))


work = os.path.join(cmake_build_dir(), "setuptools")
os.makedirs(work, exist_ok=True)
setup(
    version=version(),
    packages=["canonform"],
    package_dir={"": "python"},
    package_data={"canonform": ["py.typed"]},
    ext_modules=[Extension("canonform._canonform", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    options={"build": {"build_base": work}, "egg_info": {"egg_base": work}},
)
