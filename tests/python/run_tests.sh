#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Python package as a user meets it (ctest python.module): a wheel built from the repository by
# pip with Debian's setuptools and no network, reusing this build's package and library
# (CANONFORM_PYTHON_BUILD_DIR: nothing is compiled again), installed into a fresh venv of Debian's
# Python (--system-site-packages: its numpy, pytest and matplotlib), then pytest on tests/python/
# with the venv's Python from outside the source tree. Writes only under WORK_DIR.
#   run_tests.sh SOURCE_DIR BUILD_DIR CANONFORM_TOOL WORK_DIR [pytest arguments]
set -euo pipefail
src=$(realpath "$1"); build=$(realpath "$2"); tool=$(realpath "$3"); work=$4; shift 4
py=/usr/bin/python3
rm -rf "$work"
mkdir -p "$work/dist"
work=$(realpath "$work")
t0=$(date +%s.%N)
# Caches (pip's, matplotlib's font list) go under WORK_DIR too, not into the user's home.
export XDG_CACHE_HOME=$work/cache MPLCONFIGDIR=$work/matplotlib PIP_NO_CACHE_DIR=1 PIP_DISABLE_PIP_VERSION_CHECK=1
CANONFORM_PYTHON_BUILD_DIR=$build "$py" -m pip wheel --no-build-isolation --no-index --no-deps --quiet \
  --wheel-dir "$work/dist" "$src"
t1=$(date +%s.%N)
"$py" -m venv --system-site-packages --without-pip "$work/venv"
# the venv has no pip of its own: Debian's (from the system site packages) installs into it
"$work/venv/bin/python" -m pip install --no-index --no-deps --quiet "$work"/dist/canonform-*.whl
t2=$(date +%s.%N)
printf '[python] wheel built in %.1f s, venv made and wheel installed in %.1f s\n' \
  "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)"
cd "$work"
PYTHONDONTWRITEBYTECODE=1 MPLBACKEND=Agg CANONFORM_TOOL=$tool CANONFORM_SOURCE_DIR=$src \
  "$work/venv/bin/python" -m pytest -p no:cacheprovider --basetemp="$work/tmp" -q -rs "$src/tests/python" "$@"
printf '[python] pytest in %.1f s\n' "$(echo "$(date +%s.%N) - $t2" | bc)"
