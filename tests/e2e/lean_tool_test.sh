#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The tool's two programs (apps/canonform/main.cpp): `canonform` carries the core commands and
# descriptor and distance (the views area) without Qt, OpenCV, FAISS, BLAS or OpenMP, and runs
# `canonform-full` (beside it) for the others and for `descriptor --sift opencv`, with the idle
# thread pools' settings in its environment.
#   lean_tool_test.sh CANONFORM WORKDIR
set -u
cf=$(realpath "$1"); work=$2
cff=$(dirname "$cf")/canonform-full
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1

needed=$(objdump -p "$cf" | awk '$1 == "NEEDED" {print $2}')
extra=$(grep -E '^lib(Qt5|opencv|faiss|blas|openblas|lapack|gomp|gfortran)' <<< "$needed" | tr '\n' ' ')
check "canonform needs no Qt, OpenCV, FAISS, BLAS, LAPACK or OpenMP${extra:+ (it needs $extra)}" test -z "$extra"
check "canonform-full is beside it" test -x "$cff"
check "the same --version" test "$("$cf" --version)" = "$("$cff" --version)"

"$cf" generate fig.ply --vertices 800 --pose 4 > /dev/null
"$cf" canonical fig.ply lean.ply --quiet --threads 2
"$cff" canonical fig.ply full.ply --quiet --threads 2
check "canonical: the same bytes from both programs" cmp -s lean.ply full.ply
check "a core command: the same help from both" test "$("$cf" canonical --help)" = "$("$cff" canonical --help)"
check "a command of canonform-full through canonform: the same help" \
  test "$("$cf" views --help)" = "$("$cff" views --help)"
for c in descriptor distance; do
  check "$c: the same help from both" test "$("$cf" $c --help)" = "$("$cff" $c --help)"
done
check "the whole command list through canonform" test "$("$cf" --help)" = "$("$cff" --help)"
# same_failure DESCRIPTION STATUS ARGS...: both programs fail on ARGS with exit status STATUS and the
# same message
same_failure() {
  local d=$1 want=$2; shift 2
  "$cf" "$@" > lean.out 2>&1; lean_status=$?
  "$cff" "$@" > full.out 2>&1; full_status=$?
  check "$d: the same message and status $want from both ($(head -1 full.out))" \
    test "$lean_status" = "$want" -a "$full_status" = "$want" -a "$(cat lean.out)" = "$(cat full.out)"
}
same_failure "an unknown command" 2 frobnicate

# descriptor and distance in both programs: the same bytes (views of 128 pixels, a codebook of
# random training descriptors: the cheapest; the second mesh is the canonical form above), the same
# messages for bad input.
small=(--image-size 128)
"$cff" codebook cb.bin fig.ply --words 20 --training random "${small[@]}" > /dev/null 2>&1
for p in lean full; do
  prog=$cf; [ $p = full ] && prog=$cff
  "$prog" descriptor fig.ply $p.cfvd --codebook cb.bin "${small[@]}" &&
    "$prog" descriptor lean.ply ${p}2.cfvd --codebook cb.bin "${small[@]}" &&
    "$prog" descriptor fig.ply ${p}_raw.cfvd "${small[@]}" &&
    "$prog" distance $p.bin $p.cfvd ${p}2.cfvd --threads 2 2> /dev/null
done
check "descriptor: the same bytes from both programs" cmp -s lean.cfvd full.cfvd
check "descriptor: the same bytes from both programs (a second mesh)" cmp -s lean2.cfvd full2.cfvd
check "descriptor, raw SIFT features: the same bytes from both programs" cmp -s lean_raw.cfvd full_raw.cfvd
check "distance: the same bytes from both programs" cmp -s lean.bin full.bin
check "distance: the same text from both programs" cmp -s lean.bin.csv full.bin.csv
same_failure "descriptor of a missing mesh" 1 descriptor missing.ply x.cfvd
same_failure "descriptor with an unknown extractor" 2 descriptor fig.ply x.cfvd --sift frobnicate
same_failure "descriptor without OUT" 2 descriptor fig.ply
same_failure "distance of raw SIFT features" 1 distance x.bin lean.cfvd lean_raw.cfvd
same_failure "distance of one file" 2 distance x.bin lean.cfvd
check "bad input: nothing written" test ! -e x.cfvd -a ! -e x.bin

# `--sift opencv`: canonform runs canonform-full for it, which has it where the build has OpenCV
# (and otherwise says the extractor is not part of the program).
if "$cff" descriptor fig.ply full_cv.cfvd --codebook cb.bin --sift opencv "${small[@]}" 2> cv.err; then
  "$cf" descriptor fig.ply lean_cv.cfvd --codebook cb.bin --sift=opencv "${small[@]}"
  check "--sift=opencv through canonform: the same bytes" cmp -s lean_cv.cfvd full_cv.cfvd
else
  echo "  (canonform-full has no OpenCV SIFT: $(head -1 cv.err))"
  same_failure "--sift opencv where the build has no OpenCV" 1 descriptor fig.ply x.cfvd --sift opencv
fi

# The settings reach canonform-full, unless set already: read from /proc/PID/environ (the
# environment a program started with) while canonform-full waits to read its input, a FIFO.
mkfifo wait.ply
unset OPENBLAS_THREAD_TIMEOUT OMP_WAIT_POLICY
environ_of_full() {
  "$cf" codebook cb.bin wait.ply --words 20 > /dev/null 2>&1 &
  local pid=$! env=""
  for _ in $(seq 500); do
    env=$(tr '\0' '\n' < "/proc/$pid/environ" 2> /dev/null | grep -E '^(OPENBLAS_THREAD_TIMEOUT|OMP_WAIT_POLICY)=' | sort | tr '\n' ' ')
    [[ $env == *OMP_WAIT_POLICY* ]] && break  # after the exec (the lean process has neither)
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.01
  done
  kill "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  echo "$env"
}
got=$(environ_of_full)
check "canonform-full started with OMP_WAIT_POLICY=PASSIVE OPENBLAS_THREAD_TIMEOUT=4 (got: $got)" \
  test "$got" = "OMP_WAIT_POLICY=PASSIVE OPENBLAS_THREAD_TIMEOUT=4 "
got=$(OPENBLAS_THREAD_TIMEOUT=10 environ_of_full)
check "a setting of the user's is kept (got: $got)" test "$got" = "OMP_WAIT_POLICY=PASSIVE OPENBLAS_THREAD_TIMEOUT=10 "

# Without canonform-full: its commands, and `descriptor --sift opencv` in either form, fail with a
# message that names it; the lean program's own commands still run, descriptor and distance too.
mkdir alone && cp "$cf" alone/canonform
for args in "views fig.ply views_out" "descriptor fig.ply fig.cfvd --sift opencv" \
  "descriptor fig.ply fig.cfvd --sift=opencv"; do
  read -r -a a <<< "$args"
  alone/canonform "${a[@]}" > /dev/null 2> alone.err
  status=$?
  check "without canonform-full: '$args' exits 1 naming it ($(head -1 alone.err))" \
    test "$status" -eq 1 -a -n "$(grep canonform-full alone.err)"
done
check "without canonform-full: nothing written" test ! -e fig.cfvd -a ! -e views_out
check "without canonform-full: the core commands run" alone/canonform canonical fig.ply alone.ply --quiet
alone/canonform descriptor fig.ply alone.cfvd --codebook cb.bin "${small[@]}" &&
  alone/canonform distance alone.bin alone.cfvd full2.cfvd --threads 2 2> /dev/null
same_files() { cmp -s "$1" "$2" && cmp -s "$3" "$4"; }
check "without canonform-full: descriptor and distance run, the same bytes" \
  same_files alone.cfvd full.cfvd alone.bin full.bin
finish
