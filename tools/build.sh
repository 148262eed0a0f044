#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Configures and builds canonform in ./build (or $CANONFORM_BUILD_DIR). Runs tools/setup.sh first,
# for the same purpose (what it installs and fetches):
#
#   tools/build.sh             everything: the core, the plugins for the installed MeshLab (float,
#                              build/meshlab/plugins: 2020.09 on Debian bookworm, 2022.02 on trixie,
#                              2025.07 on forky; with the canonform-meshlab runner from 2022.02 on),
#                              the canonform tool, the tests and the benchmarks, the Python module
#   tools/build.sh --example   what README command 1 uses (tools/run_example.sh): the library, the
#                              tool and the installed MeshLab's plugins. On a build folder that is
#                              configured already, its other options stay as they are.
#   tools/build.sh --plugins   what tools/package.sh packages: the plugins (and canonform-meshlab)
#                              alone (the `plugins` target), configured without OpenCV or FAISS,
#                              the tool or the tests (also CANONFORM_PLUGINS_ONLY=1)
#   tools/build.sh --windows   the Windows build (docs/windows.md): canonform.dll (the C API),
#                              canonform.exe, the release zip, the wheel (py3-none-win_amd64) and
#                              the Windows tests' programs
#                              cross-built with MinGW-w64
#                              (cmake/mingw-w64-x86_64.cmake) in build/windows (or
#                              $CANONFORM_WINDOWS_BUILD_DIR; more CMake arguments in
#                              $CANONFORM_WINDOWS_CMAKE_ARGS); tools/wine.sh runs them
#   --configure-only           (with any of them) the set-up and CMake's configuration, no build
#
# Everything, on bookworm, also has, unless set to 0: CANONFORM_MESHLAB2022 and CANONFORM_MESHLAB2025,
# both plugins for pymeshlab 2022.2 / 2025.7 (double, build/pymeshlab2022/ and build/pymeshlab2025/)
# with meshlab-common built here and the pymeshlab harness; and, as root, CANONFORM_HOSTS, the tests
# in trixie's real MeshLab (tools/host.sh; forky's too with CANONFORM_CMAKE_ARGS=-DCANONFORM_HOST_FORKY=ON),
# and with them the portable archives' tests, forky's MeshLab among them (tests/CMakeLists.txt:
# portable.*; CANONFORM_CMAKE_ARGS=-DCANONFORM_PORTABLE_TESTS=OFF skips them);
# and CANONFORM_DOCS_TESTS, the documentation's tests (MkDocs site, Chromium, examples). Elsewhere
# these are off unless set to 1. CANONFORM_PYTHON=0 leaves out the Python module (python/).
# CANONFORM_WINDOWS=1 adds the Windows build's tests (ctest -L windows: a MinGW-w64 cross build and
# Wine; on bookworm). They are not in the default run (CI's time: docs/testing.md, "Windows").
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
mode=all
[ "${CANONFORM_PLUGINS_ONLY:-0}" = 1 ] && mode=plugins
configure_only=0
for a in "$@"; do
  case "$a" in
    --example) mode=example ;;
    --plugins) mode=plugins ;;
    --windows) mode=windows ;;
    --configure-only) configure_only=1 ;;
    *) echo "usage: $0 [--example | --plugins | --windows] [--configure-only]" >&2; exit 2 ;;
  esac
done
"$here/tools/setup.sh" "$mode"
if [ "$mode" = windows ]; then
  build=${CANONFORM_WINDOWS_BUILD_DIR:-$build/windows}
fi
mkdir -p "$build"
log="$build/build.log"
onoff() { if [ "$1" = 1 ]; then echo ON; else echo OFF; fi; }
def=0
[ "$mode" != windows ] && [ "$("$here/tools/setup.sh" --meshlab)" = 2020.09 ] && def=1
if [ "$(id -u)" -eq 0 ]; then root=$def; else root=0; fi
targets=()  # empty: all
case "$mode" in
  all)
    opts=(-DCANONFORM_BUILD_TOOLS=ON -DCANONFORM_BUILD_TESTS=ON -DCANONFORM_BUILD_BENCH=ON -DCANONFORM_RETRIEVAL=ON
          -DCANONFORM_WITHOUT_FAISS=OFF -DCANONFORM_WITHOUT_OPENCV=OFF
          -DCANONFORM_PYTHON="$(onoff "${CANONFORM_PYTHON:-1}")"
          -DCANONFORM_MESHLAB2022="$(onoff "${CANONFORM_MESHLAB2022:-$def}")"
          -DCANONFORM_MESHLAB2025="$(onoff "${CANONFORM_MESHLAB2025:-$def}")"
          -DCANONFORM_HOSTS="$(onoff "${CANONFORM_HOSTS:-$root}")"
          -DCANONFORM_DOCS_TESTS="$(onoff "${CANONFORM_DOCS_TESTS:-$def}")"
          -DCANONFORM_WINDOWS_TESTS="$(onoff "${CANONFORM_WINDOWS:-0}")" -DCANONFORM_UNITY_BUILD=ON) ;;
  example)
    # what the example needs on; the rest off in a new build folder, else as configured
    # (OpenCV, whose SIFT extractor is only for comparison, is left out of a new build folder.)
    opts=(-DCANONFORM_PLUGINS=ON -DCANONFORM_BUILD_PLUGINS=ON -DCANONFORM_VIEWS=ON -DCANONFORM_RETRIEVAL=ON
          -DCANONFORM_BUILD_TOOLS=ON -DCANONFORM_WITHOUT_FAISS=OFF -DCANONFORM_UNITY_BUILD=ON)
    [ -f "$build/CMakeCache.txt" ] ||
      opts+=(-DCANONFORM_BUILD_TESTS=OFF -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_PYTHON=OFF -DCANONFORM_MESHLAB2022=OFF
             -DCANONFORM_MESHLAB2025=OFF -DCANONFORM_HOSTS=OFF -DCANONFORM_DOCS_TESTS=OFF -DCANONFORM_WITHOUT_OPENCV=ON)
    targets=(plugins canonform) ;;
  plugins)
    opts=(-DCANONFORM_BUILD_TOOLS=OFF -DCANONFORM_BUILD_TESTS=OFF -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_PYTHON=OFF
          -DCANONFORM_WITHOUT_FAISS=ON -DCANONFORM_WITHOUT_OPENCV=ON -DCANONFORM_MESHLAB2022=OFF
          -DCANONFORM_MESHLAB2025=OFF -DCANONFORM_HOSTS=OFF -DCANONFORM_DOCS_TESTS=OFF)
    targets=(plugins) ;;
  windows)
    # (cmake/mingw-w64-x86_64.cmake sets what Windows leaves out: OpenCV, FAISS, Qt, the plugins)
    opts=(--toolchain "$here/cmake/mingw-w64-x86_64.cmake" -DCANONFORM_PYTHON=ON ${CANONFORM_WINDOWS_CMAKE_ARGS:-})
    targets=(canonform canonform_tests canonform_c canonform_c_api_test windows_zip windows_wheel) ;;
esac
echo "[build] configuring$([ "$configure_only" = 1 ] || echo " and building${targets[*]:+ ${targets[*]}}") in $build (log: $log)"
step() {
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "${opts[@]}" ${CANONFORM_CMAKE_ARGS:-} || return 1
  [ "$configure_only" = 1 ] && return 0
  cmake --build "$build" -j"$(nproc)" ${targets[@]+--target "${targets[@]}"}
}
if ! step > "$log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$log" | head -120
  echo "[build] FAILED (full log: $log)" >&2
  exit 1
fi
[ "$configure_only" = 1 ] && { echo "[build] configured"; exit 0; }
warnings=$(grep -c "warning:" "$log" || true)
echo "[build] done ($warnings compiler warnings)"
