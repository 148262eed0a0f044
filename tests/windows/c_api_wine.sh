#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The C API's test program of the Windows build ($CANONFORM_C_API_EXE, canonform_c_api_test.exe,
# beside which the test build puts nothing: canonform.dll is found through WINEPATH) under Wine
# (tools/wine.sh), with its arguments and exit status; for tests/c_api/run_test.sh.
set -euo pipefail
exe=${CANONFORM_C_API_EXE:?CANONFORM_C_API_EXE names canonform_c_api_test.exe}
dll_dir=$(cd "$(dirname "$exe")/../src" && pwd)
export WINEPATH="Z:${dll_dir//\//\\}${WINEPATH:+;$WINEPATH}"
exec "$(dirname "$(realpath "$0")")/../../tools/wine.sh" "$exe" "$@"
