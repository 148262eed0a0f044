#!/usr/bin/env bash
# README command 2: sets up, builds, and runs every test (unit, property and end-to-end tests
# through the canonform tool and the real meshlabserver) with ctest.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
cd "$build"
ctest --output-on-failure -j"$(nproc)" "$@"
