#!/usr/bin/env bash
# Configures and builds canonform in ./build (or $CANONFORM_BUILD_DIR): the core, the MeshLab
# 2020.09 plugins (float), the canonform tool, the tests and the benchmarks, and - unless
# CANONFORM_MESHLAB2022=0 - both plugins again for MeshLab 2022.02 / pymeshlab 2022.2 (double,
# in build/meshlab2022/plugins) with MeshLab 2022.02's meshlab-common and their test harness.
# Runs tools/setup.sh first.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
"$here/tools/setup.sh"
mkdir -p "$build"
log="$build/build.log"
echo "[build] configuring and building in $build (log: $log)"
if [ "${CANONFORM_MESHLAB2022:-1}" = "0" ]; then ml2022=OFF; else ml2022=ON; fi
if ! { cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCANONFORM_MESHLAB2022=$ml2022 ${CANONFORM_CMAKE_ARGS:-} &&
       cmake --build "$build" -j"$(nproc)"; } >"$log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$log" | head -120
  echo "[build] FAILED (full log: $log)" >&2
  exit 1
fi
warnings=$(grep -c "warning:" "$log" || true)
echo "[build] done ($warnings compiler warnings)"
