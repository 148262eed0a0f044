#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Configures and builds canonform in ./build (or $CANONFORM_BUILD_DIR): the core, the plugins for
# the installed MeshLab (float, build/meshlab/plugins: 2020.09 on Debian bookworm, 2022.02 on trixie,
# 2025.07 on forky; with the canonform-meshlab runner from 2022.02 on), the canonform tool, the
# tests and the benchmarks. On bookworm also, unless set to 0: CANONFORM_MESHLAB2022 and
# CANONFORM_MESHLAB2025, both plugins for pymeshlab 2022.2 / 2025.7 (double, build/pymeshlab2022/
# and build/pymeshlab2025/) with meshlab-common built here and the pymeshlab harness; and, as root,
# CANONFORM_HOSTS, the tests in trixie's and forky's real MeshLab (tools/host.sh), and with them the
# portable archives' tests (tests/CMakeLists.txt: portable.*; CANONFORM_CMAKE_ARGS=-DCANONFORM_PORTABLE_TESTS=OFF
# skips them); and CANONFORM_DOCS_TESTS, the documentation's tests (MkDocs site, Chromium, examples).
# Elsewhere these are off unless set to 1. CANONFORM_PLUGINS_ONLY=1 builds only what tools/package.sh
# packages (the plugins and canonform-meshlab). CANONFORM_PYTHON=0 leaves out the Python module
# (python/). Runs tools/setup.sh first.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
"$here/tools/setup.sh"
mkdir -p "$build"
log="$build/build.log"
echo "[build] configuring and building in $build (log: $log)"
onoff() { if [ "$1" = 1 ]; then echo ON; else echo OFF; fi; }
if [ "$("$here/tools/setup.sh" --meshlab)" = 2020.09 ]; then def=1; else def=0; fi
if [ "$(id -u)" -eq 0 ]; then root=$def; else root=0; fi
# CANONFORM_PLUGINS_ONLY=1: only what the Debian package holds (plugins, canonform-meshlab)
if [ "${CANONFORM_PLUGINS_ONLY:-0}" = 1 ]; then
  only=(-DCANONFORM_BUILD_TOOLS=OFF -DCANONFORM_BUILD_TESTS=OFF -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_PYTHON=OFF)
else
  only=(-DCANONFORM_BUILD_TOOLS=ON -DCANONFORM_BUILD_TESTS=ON -DCANONFORM_BUILD_BENCH=ON
        -DCANONFORM_PYTHON="$(onoff "${CANONFORM_PYTHON:-1}")")
fi
opts=("${only[@]}" -DCANONFORM_MESHLAB2022="$(onoff "${CANONFORM_MESHLAB2022:-$def}")"
      -DCANONFORM_MESHLAB2025="$(onoff "${CANONFORM_MESHLAB2025:-$def}")"
      -DCANONFORM_HOSTS="$(onoff "${CANONFORM_HOSTS:-$root}")"
      -DCANONFORM_DOCS_TESTS="$(onoff "${CANONFORM_DOCS_TESTS:-$def}")")
if ! { cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "${opts[@]}" ${CANONFORM_CMAKE_ARGS:-} &&
       cmake --build "$build" -j"$(nproc)"; } >"$log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$log" | head -120
  echo "[build] FAILED (full log: $log)" >&2
  exit 1
fi
warnings=$(grep -c "warning:" "$log" || true)
echo "[build] done ($warnings compiler warnings)"
