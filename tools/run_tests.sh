#!/usr/bin/env bash
# README command 2: sets up, builds, and runs every test (unit, property and end-to-end tests
# through the canonform tool and the real meshlabserver) with ctest; then, unless
# CANONFORM_SANITIZER_TESTS=0 or ctest arguments are given, the unit and end-to-end tests again
# under AddressSanitizer + UndefinedBehaviorSanitizer with a bounded run of every fuzz target
# (tools/sanitizer_tests.sh).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
cd "$build"
ctest --output-on-failure -j"$(nproc)" "$@"
if [ $# -eq 0 ] && [ "${CANONFORM_SANITIZER_TESTS:-1}" != "0" ]; then
  "$here/tools/sanitizer_tests.sh"
fi
