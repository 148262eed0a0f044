#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The same results on every x86-64 CPU: the canonform tool run as another CPU by qemu user-mode
# emulation (Debian's qemu-user) against the same binary run natively, on the same input files.
#   cpu_matrix_test.sh prepare CANONFORM WORKDIR           native inputs and reference outputs
#   cpu_matrix_test.sh compare CANONFORM PLYCHECK WORKDIR MODEL
#   cpu_matrix_test.sh unit MODEL TESTS GTEST_FILTER      the unit tests as MODEL
# MODEL is a qemu CPU model: qemu64 (x86-64 baseline: no SSE4, AVX, FMA; glibc's libm takes its
# SSE2 code, Eigen reads a 64 KiB L1 cache from CPUID), Haswell (Intel, AVX2 + FMA: libm's FMA
# code), EPYC (AMD, AVX2 + FMA). Compared, bit for bit (`cmp`): the conformal factor, the
# Euclidean canonical forms (variants N and A), the three geodesic forms (least squares, classical,
# landmark MDS), the view descriptors with the default SIFT backend, and their distance matrix; a
# collection index (its first pass: axes and codes) and a two-stage query.
# Stated tolerance: none - the library's results are the same bits on every CPU (docs/cpu.md).
# For a difference the script prints its size (largest coordinate difference of a form; clock
# distance between the two descriptors of one mesh next to that between the two meshes).
# Exit 77 (ctest: skipped) when qemu-x86_64 is not installed.
set -u
mode=$1
if ! command -v qemu-x86_64 > /dev/null 2>&1; then
  echo "skipped: qemu-x86_64 is not installed (Debian's qemu-user; tools/setup.sh installs it on bookworm)"
  exit 77
fi
case "$mode" in
  prepare) cf=$(realpath "$2"); work=$3 ;;
  compare) cf=$(realpath "$2"); plycheck=$(realpath "$3"); work=$4; model=$5 ;;
  unit) echo "the unit tests as CPU model $2 (qemu-x86_64 -cpu $2)"
        exec qemu-x86_64 -cpu "$2" "$3" --gtest_filter="$4" --gtest_brief=1 2> >(grep -v "TCG doesn't support" >&2) ;;
  *) echo "usage: $0 prepare CANONFORM WORKDIR | compare CANONFORM PLYCHECK WORKDIR MODEL | unit MODEL TESTS FILTER"; exit 2 ;;
esac
. "$(dirname "$0")/lib.sh"

# Where the tool is two programs, canonform runs canonform-full for the commands beyond its own
# (the core ones, descriptor and distance: apps/canonform/main.cpp); under qemu-x86_64 that exec
# would run natively, so those commands call canonform-full directly.
cff=$(dirname "$cf")/canonform-full
[ -x "$cff" ] || cff=$cf

# run_all DIR RUNNER...: every compared output of the tool into DIR, the tool started by RUNNER
run_all() {
  local out=$1; shift
  mkdir -p "$out"
  local t=(--threads 2 --quiet)  # the same thread count everywhere (qemu runs threads natively)
  "$@" "$cf" conformal in/A.ply "$out/conformal.ply" > /dev/null &&
  "$@" "$cf" canonical in/A.ply "$out/euclidean-N.ply" --method euclidean-N "${t[@]}" &&
  "$@" "$cf" canonical in/A.ply "$out/euclidean-A.ply" --method euclidean-A "${t[@]}" &&
  for m in geodesic-ls geodesic-classical geodesic-fast; do
    "$@" "$cf" canonical in/S.ply "$out/$m.ply" --method "$m" "${t[@]}" || return 1
  done &&
  "$@" "$cf" descriptor in/A.ply "$out/A.cfvd" --codebook in/cb.bin > /dev/null &&
  "$@" "$cf" descriptor in/S.ply "$out/S.cfvd" --codebook in/cb.bin > /dev/null &&
  "$@" "$cf" distance "$out/distances.bin" "$out/A.cfvd" "$out/S.cfvd" --threads 2 > /dev/null &&
  # The collection index (first pass trained and coded) and a two-stage query (first pass forced
  # by --candidates), on a copy of the native run folder; the query's timings left out.
  rm -rf "$out.run" && cp -r in/run "$out.run" &&
  "$@" "$cff" index "$out.run" 2> /dev/null && cp "$out.run/none/index.cfci" "$out/index.cfci" &&
  "$@" "$cff" query "$out.run" in/S.ply --top 3 --candidates 3 --json --threads 2 |
    /usr/bin/python3 -c 'import json, sys; j = json.load(sys.stdin); [j.pop(k) for k in ("describe_seconds", "search_seconds")]; print(json.dumps(j))' > "$out/query.json"
}

if [ "$mode" = prepare ]; then
  rm -rf "$work"; mkdir -p "$work/in"; cd "$work" || exit 1
  echo "inputs and native outputs in $work"
  # A procedural figure of 1000 vertices (pose 4: the rectilinearity pose wins), a smaller one
  # for the geodesic forms (all pairs), and a codebook trained natively on both.
  check "generate the inputs" "$cf" generate in/A.ply --vertices 1000 --pose 4
  check "generate the geodesic input" "$cf" generate in/S.ply --vertices 600 --pose 5
  check "train the codebook" "$cf" codebook in/cb.bin in/A.ply in/S.ply --words 50
  check "generate a small collection" "$cf" generate --collection in/coll --vertices 500 --poses 2 --classes standard,long-arms,short-legs
  check "a retrieval run of it (method none)" bash -c "\"$cf\" retrieve --dataset in/coll --out in/run --method none --words 30 --threads 2 > /dev/null 2>&1"
  check "native outputs" run_all native
  finish
  exit
fi

cd "$work" || exit 1
[ -d native ] || { echo "no native outputs in $work (run the prepare step first)"; exit 1; }
echo "the tool as CPU model $model (qemu-x86_64 -cpu $model) against the native run"
if ! run_all "$model" qemu-x86_64 -cpu "$model" 2> "$model.log"; then
  fail "the tool ran as $model"; tail -5 "$model.log"; finish; exit
fi
for f in native/*; do
  name=${f#native/}
  if cmp -s "$f" "$model/$name"; then
    pass "$name: the same bits"
  else
    case "$name" in
      *.ply) fail "$name differs: $("$plycheck" "$model/$name" "$f" | python3 -c 'import json,sys; j=json.load(sys.stdin); print("max coordinate difference", j.get("max_position_diff"), "quality", j.get("max_quality_diff"))')" ;;
      *.cfvd) "$cf" distance "$model/d_$name.bin" "$model/$name" "$f" native/S.cfvd native/A.cfvd --threads 2 > /dev/null 2>&1
              fail "$name differs: clock distance to the native descriptor, and between the two meshes (native): $(awk -F, 'NR == 1 {a = $2} NR == 3 {b = $4} END {print a, "vs", b}' "$model/d_$name.bin.csv")" ;;
      *) fail "$name differs" ;;
    esac
  fi
done
finish
