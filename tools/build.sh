#!/usr/bin/env bash
# Configures and builds canonform in ./build (or $CANONFORM_BUILD_DIR): the core, the MeshLab
# plugins, the canonform tool, the tests and the benchmarks. Runs tools/setup.sh first.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
"$here/tools/setup.sh"
mkdir -p "$build"
log="$build/build.log"
echo "[build] configuring and building in $build (log: $log)"
if ! { cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release ${CANONFORM_CMAKE_ARGS:-} &&
       cmake --build "$build" -j"$(nproc)"; } >"$log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$log" | head -120
  echo "[build] FAILED (full log: $log)" >&2
  exit 1
fi
warnings=$(grep -c "warning:" "$log" || true)
echo "[build] done ($warnings compiler warnings)"
