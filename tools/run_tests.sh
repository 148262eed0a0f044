#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# README command 2: sets up, checks the style (tools/check_style.sh), builds, and runs every test
# (unit, property and end-to-end tests through the canonform tool and the real meshlabserver) with
# ctest; then, unless CANONFORM_SANITIZER_TESTS=0 or ctest arguments are given, the unit and
# end-to-end tests again under AddressSanitizer + UndefinedBehaviorSanitizer with a bounded run of
# every fuzz target (tools/sanitizer_tests.sh; its build runs niced alongside ctest).
# The root filesystems the configured tests use (build/host_suites.txt, tests/CMakeLists.txt:
# canonform_uses_hosts) are made at the start, alongside the build (mostly download and unpacking),
# and the plugins built in those that have a build of their own (trixie; forky with
# -DCANONFORM_HOST_FORKY=ON: tools/host.sh --prepare); ctest's tests wait for what they need
# (tools/host.sh's locks).
# The tests leave the machine as they found it: after the set-up (which may install packages), the
# MeshLab plugin folder, /usr/local and the dpkg database are listed, and listed again at the end;
# any difference fails the run. Each stage's wall time and CPU time (user + system, of every process
# the stage ran) are printed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
tck=$(getconf CLK_TCK)
# CPU seconds of this script's finished children and their descendants (/proc: cutime + cstime)
cpu() { local f; read -r -a f < <(sed 's/^.*) //' "/proc/$$/stat"); echo $(( (f[13] + f[14]) / tck )); }
t0=$(date +%s) c0=$(cpu)
stage() { echo "[tests] $1: $(( $(date +%s) - $2 )) s, $(( $(cpu) - $3 )) CPU s"; }

"$here/tools/setup.sh"
stage "set-up" "$t0" "$c0"
# The style (tools/check_style.sh: clang-format, commit subjects); a failure fails the run at its end.
style_rc=0
[ $# -ne 0 ] || "$here/tools/check_style.sh" || style_rc=$?
mkdir -p "$build"
machine_state() {
  # What a test must not change. Python's byte-code caches are left out (an import may write them).
  { find /usr/lib/x86_64-linux-gnu/meshlab /usr/local -path '*/__pycache__' -prune -o -printf '%p %y %s %T@ %m\n' 2>/dev/null | sort
    md5sum /var/lib/dpkg/status; ls /var/lib/dpkg/info | md5sum; }
}
machine_state > "$build/machine_state.before"

t1=$(date +%s) c1=$(cpu)
CANONFORM_BUILD_DIR=$build "$here/tools/build.sh" --configure-only
# The root filesystems and their builds, one process each, while the build compiles; a test that
# needs one waits for it (tools/host.sh's locks), and fails if it failed. Not for a run of some
# tests (ctest arguments): those make what they use themselves.
hosts_pids=()
trap '[ ${#hosts_pids[@]} -eq 0 ] || kill "${hosts_pids[@]}" 2>/dev/null || true' EXIT  # a failed build
suites=()
[ $# -eq 0 ] && [ -f "$build/host_suites.txt" ] && mapfile -t suites < "$build/host_suites.txt"
for s in "${suites[@]}"; do
  "$here/tools/host.sh" --prepare "$s" > "$build/host_prepare.$s.log" 2>&1 &
  hosts_pids+=($!)
done
[ ${#suites[@]} -eq 0 ] || echo "[tests] root filesystems made and prepared alongside the build: ${suites[*]}"
CANONFORM_BUILD_DIR=$build "$here/tools/build.sh"
stage "build (the root filesystems alongside: their CPU counts in ctest's)" "$t1" "$c1"
t2=$(date +%s) c2=$(cpu)
# The sanitizer build starts now, at the lowest priority, so that it uses what ctest leaves idle
# (root filesystems being downloaded and unpacked, single-threaded tests); its tests run after ctest.
san=0
if [ $# -eq 0 ] && [ "${CANONFORM_SANITIZER_TESTS:-1}" != "0" ]; then
  san=1
  setsid nice -n 19 "$here/tools/sanitizer_tests.sh" --build-only > "$build/sanitizer_build.log" 2>&1 &
  san_pid=$!
fi
ctest_rc=0
(cd "$build" && ctest --output-on-failure -j"$(nproc)" "$@") || ctest_rc=$?
hosts_rc=0
for p in "${hosts_pids[@]}"; do wait "$p" || hosts_rc=1; done  # done: the tests waited for them
hosts_pids=()
cat "$build"/host_prepare.*.log 2>/dev/null | grep -E "ready in|built and installed|error" || true
[ "$hosts_rc" = 0 ] || echo "[tests] making or preparing a root filesystem failed (build/host_prepare.*.log)"
stage "ctest (with the root filesystems; the sanitizer build alongside, not counted)" "$t2" "$c2"
if [ "$ctest_rc" != 0 ] && [ "$san" = 1 ]; then
  kill -- "-$san_pid" 2>/dev/null || true  # ctest failed: stop the sanitizer build (its own process group)
  exit "$ctest_rc"
fi
if [ "$san" = 1 ]; then
  t3=$(date +%s) c3=$(cpu)
  san_rc=0
  wait "$san_pid" || san_rc=$?
  cat "$build/sanitizer_build.log"
  stage "sanitizer build, the rest after ctest (CPU: the whole build)" "$t3" "$c3"
  [ "$san_rc" = 0 ] || exit "$san_rc"
  t4=$(date +%s) c4=$(cpu)
  "$here/tools/sanitizer_tests.sh"
  stage "sanitizer tests" "$t4" "$c4"
fi
[ "$ctest_rc" = 0 ] || exit "$ctest_rc"
[ "$style_rc" = 0 ] || { echo "[tests] FAILED: the style check (tools/check_style.sh, printed after the set-up)" >&2; exit 1; }

machine_state > "$build/machine_state.after"
if ! diff "$build/machine_state.before" "$build/machine_state.after" > "$build/machine_state.diff"; then
  echo "[tests] FAILED: the tests changed the machine (MeshLab's plugin folder, /usr/local or dpkg's database):" >&2
  head -40 "$build/machine_state.diff" >&2
  exit 1
fi
echo "[tests] the machine is as the tests found it (MeshLab's plugin folder, /usr/local, dpkg's database)"
stage "all" "$t0" "$c0"
