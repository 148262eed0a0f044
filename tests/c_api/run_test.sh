#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest c_api.test: the C API's test program (tests/c_api/c_api_test.c, compiled as C) on a figure
# and the form the canonform tool writes of it (the C API's form must be the same bytes).
#   run_test.sh C_API_TEST CANONFORM WORK_DIR
set -euo pipefail
test=$1 cf=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
"$cf" generate "$work/mesh.ply" --vertices 1500 --pose 4
"$cf" canonical "$work/mesh.ply" "$work/form.ply" --quiet
"$test" "$work" "$work/mesh.ply" "$work/form.ply"
