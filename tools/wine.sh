#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a Windows program of the cross build (cmake/mingw-w64-x86_64.cmake) under Wine 8
# (Debian's wine64; tools/setup.sh installs it on bookworm), headless and quiet:
#   tools/wine.sh PROGRAM.exe [ARGS...]
# The Wine prefix (Wine's C: drive and registry) is $WINEPREFIX, else wine-prefix/ in the build
# folder above the program (the first folder up holding CMakeCache.txt), else ./wine-prefix: never
# ~/.wine, so that the tests leave the machine as they found it. The first start makes the
# prefix (about 11 s); later starts take a fraction of a second. No X display is used or needed.
set -euo pipefail
wine=${CANONFORM_WINE:-/usr/lib/wine/wine64}
if [ ! -x "$wine" ]; then
  echo "tools/wine.sh: $wine not found (Debian's wine64 package; tools/setup.sh installs it on bookworm)" >&2
  exit 127
fi
if [ $# -lt 1 ]; then echo "usage: tools/wine.sh PROGRAM.exe [ARGS...]" >&2; exit 2; fi
if [ -z "${WINEPREFIX:-}" ]; then
  d=$(cd "$(dirname "$1")" && pwd)
  while [ "$d" != / ] && [ ! -f "$d/CMakeCache.txt" ]; do d=$(dirname "$d"); done
  [ "$d" = / ] && d=$PWD
  export WINEPREFIX="$d/wine-prefix"
fi
export WINEDEBUG=${WINEDEBUG:--all} WINEDLLOVERRIDES=${WINEDLLOVERRIDES:-winemenubuilder.exe=d} DISPLAY=
unset WAYLAND_DISPLAY
exec "$wine" "$@"
