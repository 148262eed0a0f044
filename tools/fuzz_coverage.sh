#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Line coverage of the project's readers by the fuzz corpora kept in the repository
# (tests/fuzz/corpus/) and the seeds the unit tests write: a clang build of the fuzz targets with
# source-based coverage (-fprofile-instr-generate -fcoverage-mapping, no sanitizers) in BUILD_DIR
# (default ./build-cov); the seeds come from the plain build's unit tests (UNIT_TESTS, default
# ./build/tests/canonform_tests: in the fuzz build they need a sanitizer runtime to link),
# every fuzz target run once over its inputs (-runs=0), then llvm-cov's report of the reader sources:
# src/canonform/io/*.cpp, views/descriptor_file.cpp and views/codebook.cpp. Prints the table
# (markdown) and writes BUILD_DIR/coverage/{report.txt,uncovered.txt}: uncovered.txt lists every
# line no input reaches, by file.
#   tools/fuzz_coverage.sh [BUILD_DIR]          UNIT_TESTS=PATH (a canonform_tests binary)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$(realpath -m "${1:-$here/build-cov}")
mkdir -p "$build"
log=$build/build.log
targets=(mesh_off mesh_ply mesh_obj mesh_stl descriptor codebook matrix_bin matrix_csv labels)
echo "[coverage] clang build with coverage mapping in $build (log: $log)"
CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release \
  "-DCMAKE_CXX_FLAGS=-fprofile-instr-generate -fcoverage-mapping" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fprofile-instr-generate" -DCANONFORM_FUZZ=ON -DCANONFORM_BUILD_PLUGINS=OFF \
  -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_BUILD_TOOLS=OFF -DCANONFORM_MESHLAB2022=OFF -DCANONFORM_MESHLAB2025=OFF > "$log" 2>&1
cmake --build "$build" -j"$(nproc)" --target "${targets[@]/#/fuzz_}" >> "$log" 2>&1
# The seeds: the unit tests that write them (test_util.h: fuzz_seed()).
seeds=$build/fuzz/seeds
rm -rf "$build/coverage"; mkdir -p "$build/coverage" "$seeds"
unit=${UNIT_TESTS:-$here/build/tests/canonform_tests}
if [ -x "$unit" ]; then
  CANONFORM_FUZZ_SEEDS=$seeds "$unit" --gtest_filter='MeshIo*:DescriptorFile*:Codebook*:DistanceMatrix*:Csv*:Labels*:Files*' \
    > "$build/coverage/unit.log" 2>&1 || true
else
  echo "[coverage] no unit-test binary at $unit (tools/build.sh makes it): the corpora alone are measured" >&2
fi
objects=()
for t in "${targets[@]}"; do
  bin=$build/tests/fuzz/fuzz_$t
  dirs=()
  [ -d "$here/tests/fuzz/corpus/$t" ] && dirs+=("$here/tests/fuzz/corpus/$t")
  [ -d "$seeds/$t" ] && dirs+=("$seeds/$t")
  CANONFORM_FUZZ_SCRATCH=$build/coverage/scratch LLVM_PROFILE_FILE=$build/coverage/$t.profraw "$bin" -runs=0 -rss_limit_mb=2048 "${dirs[@]}" > "$build/coverage/$t.log" 2>&1 || true
  objects+=(-object "$bin")
done
rm -rf "$build/coverage/scratch"
llvm-profdata merge -sparse "$build"/coverage/*.profraw -o "$build/coverage/all.profdata"
sources=("$here"/src/canonform/io/*.cpp "$here/src/canonform/views/descriptor_file.cpp" "$here/src/canonform/views/codebook.cpp")
llvm-cov report "${objects[@]:1}" -instr-profile="$build/coverage/all.profdata" "${sources[@]}" > "$build/coverage/report.txt"
# Uncovered lines: llvm-cov show gives an executable line that never ran the count 0.
llvm-cov show "${objects[@]:1}" -instr-profile="$build/coverage/all.profdata" "${sources[@]}" -use-color=false \
  > "$build/coverage/show_counts.txt"
awk '/^\/.*:$/ { file=$0; sub(/:$/, "", file); next }
     /^ *[0-9]+\| *0\|/ { split($0, a, "|"); gsub(/ /, "", a[1]); print file ":" a[1] ":" a[3] }' \
  "$build/coverage/show_counts.txt" > "$build/coverage/uncovered.txt" || true
echo "| file | lines | covered | line coverage |"
echo "|---|---|---|---|"
awk -v root="$here/" 'NF >= 10 && $1 ~ /\.cpp$|^TOTAL$/ {
    f = $1; sub(root, "", f); lines = $8; missed = $9; cov = $10;
    printf "| %s | %d | %d | %s |\n", f, lines, lines - missed, cov }' "$build/coverage/report.txt"
echo "[coverage] uncovered lines: $(wc -l < "$build/coverage/uncovered.txt") (list: $build/coverage/uncovered.txt)"
