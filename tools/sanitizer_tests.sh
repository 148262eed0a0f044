#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The unit tests of the library and the canonform tool's bad-input commands again in an
# AddressSanitizer + UndefinedBehaviorSanitizer build (clang, any report fails the test), and every
# libFuzzer target for a bounded time on the seeds the unit tests write (tests/fuzz). Without
# arguments the slow whole-pipeline runs that the plain build already covers are left out
# (SLOW below: the retrieval experiment's full runs, sharded runs, the collection index, the tool's
# end-to-end and sharded runs, Slurm): under the sanitizers they took most of the stage's time, and
# the code they run is run there by smaller tests too (the experiment's bad-collection and NaN-form
# tests, the stages' unit tests, the tool's bad-input commands); so are the tests that repeat one
# computation over sizes, classes or poses (the procedural figure at three targets and in every
# class and pose, the figure's checks at 10000 vertices as well as 2000, multigrid's steps on a mesh
# 4x finer, the pose searches over four and six figures): the procedural, multigrid and pose tests
# left in run the same code once. With arguments,
# they go to ctest as given. Called by tools/run_tests.sh (so CI runs it); builds in ./build-san
# (or $CANONFORM_SAN_BUILD_DIR) only what these tests need: no plugins (they run inside the
# non-instrumented meshlabserver; see docs/testing.md), no benchmarks.
# Every target in batches of source files (CMAKE_UNITY_BUILD), the library's too: its objects here
# serve only these tests (the plain build keeps one object per library source). At -O2 rather than
# the usual -O1: Eigen's templates left out of line at -O1 make the tests a quarter slower, for
# about the same build time (docs/testing.md); both sanitizers still check every access and
# operation at -O2.
#   tools/sanitizer_tests.sh [ctest arguments]     CANONFORM_FUZZ_SECONDS=N (default 5 per target)
#   tools/sanitizer_tests.sh --build-only          the build alone (run_tests.sh starts it, niced,
#                                                  while ctest runs; the second call then only tests)
set -euo pipefail
build_only=0
if [ "${1:-}" = --build-only ]; then build_only=1; shift; fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_SAN_BUILD_DIR:-$here/build-san}
mkdir -p "$build"
log="$build/build.log"
t0=$(date +%s)
echo "[sanitizers] clang ASan+UBSan+libFuzzer build in $build (log: $log)"
if ! { CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
         "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only" -DCANONFORM_SANITIZE=address,undefined \
         -DCANONFORM_FUZZ=ON -DCANONFORM_FUZZ_SECONDS="${CANONFORM_FUZZ_SECONDS:-5}" -DCANONFORM_BUILD_PLUGINS=OFF \
         -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_MESHLAB2022=OFF -DCANONFORM_PYTHON=OFF -DCMAKE_UNITY_BUILD=ON &&
       targets=$(cmake --build "$build" --target help | grep -oE '(canonform_tests|canonform_plycheck|canonform|fuzz_[a-z_]+)$' | sort -u) &&
       cmake --build "$build" -j"$(nproc)" --target $targets; } > "$log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$log" | head -80
  echo "[sanitizers] build FAILED (full log: $log)" >&2
  exit 1
fi
t1=$(date +%s)
echo "[sanitizers] built in $((t1 - t0)) s"
[ "$build_only" = 1 ] && exit 0
cd "$build"
# Reports are failures; leaks too (LeakSanitizer), except those of the libraries below us that we
# cannot fix (tests/sanitizer_suppressions.txt).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/tests/sanitizer_suppressions.txt:print_suppressions=0}
# Also left out: the tests that run no C++ of ours (layout, licence lines, a Python script): the same
# there as in the plain build; and the timing printouts (names with Timing), which only print
# seconds, meaningless under the sanitizers.
SLOW='^(Experiment\.(ASeed|Writes|AMethod|Fused)|ShardedRun\.|CollectionIndex\.|cli\.end_to_end$|cli\.sharded$|slurm\.|layout\.rules$|licence\.spdx$|tools\.paired_queries$)|Timing'
SLOW+='|^ProceduralFigure\.ValidAndRepeatableAtOtherTargets$|^ProceduralFigureClasses\.(EveryClassIsClean|RandomPoses)|^AlgebraicMultigrid\.CgStepsDoNotGrowWithTheMesh$'
SLOW+='|^Targets/ProceduralFigureAtTarget\..*/10000$|^PoseNormalization\.(BinnedCoarseSearchFindsTheSameRectilinearity|FigureIsInvariantToSimilarityTransforms)$'
if [ $# -eq 0 ]; then set -- -E "$SLOW"; fi
ctest --output-on-failure -j"$(nproc)" "$@"
echo "[sanitizers] tests in $(( $(date +%s) - t1 )) s"
