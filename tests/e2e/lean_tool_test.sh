#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The tool's two programs (apps/canonform/main.cpp): `canonform` carries the one-mesh core commands
# without Qt, OpenCV, FAISS, BLAS or OpenMP, and runs `canonform-full` (beside it) for the others,
# with the idle thread pools' settings in its environment.
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
  test "$("$cf" descriptor --help)" = "$("$cff" descriptor --help)"
check "the whole command list through canonform" test "$("$cf" --help)" = "$("$cff" --help)"
"$cf" frobnicate > lean.out 2>&1; lean_status=$?
"$cff" frobnicate > full.out 2>&1; full_status=$?
check "an unknown command: the same message and status $full_status through canonform" \
  test "$lean_status" = "$full_status" -a "$full_status" = 2 -a "$(cat lean.out)" = "$(cat full.out)"

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

# Without canonform-full: its commands fail with a message that names it; the core ones still run.
mkdir alone && cp "$cf" alone/canonform
alone/canonform descriptor fig.ply fig.cfvd > /dev/null 2> alone.err
status=$?
check "without canonform-full: exit 1 naming it ($(head -1 alone.err))" \
  test "$status" -eq 1 -a -n "$(grep canonform-full alone.err)"
check "without canonform-full: nothing written" test ! -e fig.cfvd
check "without canonform-full: the core commands run" alone/canonform canonical fig.ply alone.ply --quiet
finish
