#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Windows build for the `windows` tests: tools/build.sh --windows into WINBUILD, then Wine's
# prefix made there by a first start of canonform.exe (about 11 s, once), so that the tests after
# it, which may run in parallel, find it made. Prints the build's wall and CPU seconds.
#   build_test.sh SOURCE_DIR WINBUILD
set -euo pipefail
src=$1; win=$2
t0=$(date +%s)
CANONFORM_WINDOWS_BUILD_DIR=$win /usr/bin/time -f "%e s wall, %U s user + %S s system CPU" -o "$win.time" \
  "$src/tools/build.sh" --windows
echo "[windows] build: $(cat "$win.time")"
t1=$(date +%s)
"$src/tools/wine.sh" "$win/apps/canonform.exe" --version
echo "[windows] Wine's prefix in $win/wine-prefix ready in $(( $(date +%s) - t1 )) s"
