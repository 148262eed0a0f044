#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The README's two commands as a new user runs them: on a fresh Debian bookworm as its installer
# leaves it (tools/host.sh bookworm-new: nothing of this machine's packages, the machine's own Debian
# mirror), as root, in a fresh clone of this repository's HEAD (external/ empty), one after the other
# in the order given. Each command's wall time and CPU time (user + system of all it ran) are
# printed; the first failure stops the run. Needs root (tools/host.sh).
#
#   tools/readme_commands.sh 1          command 1 (tools/run_example.sh) from bare metal
#   tools/readme_commands.sh 1 1 2 2 1  both, in both orders, each twice
#
# Command 2 (tools/run_tests.sh) runs with the arguments of CANONFORM_README_TESTS (default none:
# the whole CI, root filesystems made from nothing inside; e.g. "-L unit" for the set-up, the build
# and the unit tests alone, without the sanitizer stage). The machine and the clone are made anew
# for every call (build/hosts/bookworm-new, /tmp/canonform-readme.*) and deleted at the end unless
# CANONFORM_README_KEEP=1.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 1 ] || { echo "usage: $0 1|2 [1|2]..." >&2; exit 2; }
for c in "$@"; do case "$c" in 1|2) ;; *) echo "usage: $0 1|2 [1|2]..." >&2; exit 2 ;; esac; done
[ "$(id -u)" -eq 0 ] || { echo "$0: needs root (tools/host.sh)" >&2; exit 1; }

"$here/tools/host.sh" --make bookworm-new
state=$here/build/hosts/bookworm-new
rm -rf "$state/upper" "$state/work"  # a fresh machine: the overlay's changes of an earlier call go
work=$(mktemp -d /tmp/canonform-readme.XXXXXX)
cleanup() {
  [ "${CANONFORM_README_KEEP:-0}" = 1 ] && { echo "[readme] kept: $work, $state"; return; }
  rm -rf "$work" "$state/upper" "$state/work"
}
trap cleanup EXIT
git clone -q "$here" "$work/canonform"
git -C "$work/canonform" log -1 --format='[readme] clone of %h: %s'

n=0
for c in "$@"; do
  n=$((n + 1))
  case "$c" in
    1) cmd=(tools/run_example.sh) ;;
    2) read -r -a extra <<< "${CANONFORM_README_TESTS:-}"; cmd=(tools/run_tests.sh ${extra[@]+"${extra[@]}"}) ;;
  esac
  echo "[readme] $n: command $c (${cmd[*]}) in a Debian bookworm as installed, $(uptime | sed 's/.*load/load/')"
  start=$SECONDS
  rc=0
  # inside: the command's output, then its CPU time (bash's `times`: children's user and system)
  CANONFORM_HOST_PREPARE=0 "$here/tools/host.sh" bookworm-new bash -c \
    'cd "$1" && shift && "$@" > "$0" 2>&1; rc=$?; times >> "$0"; exit $rc' \
    "$work/command$n.log" "$work/canonform" "${cmd[@]}" || rc=$?
  wall=$((SECONDS - start))
  cpu=$(tail -n 1 "$work/command$n.log" | awk '{ s = 0; for (i = 1; i <= 2; i++) { split($i, a, /[ms]/); s += a[1] * 60 + a[2] } printf "%.0f", s }')
  grep -E "^\[(setup|build|example|tests)\]" "$work/command$n.log" | grep -v "source present\|all packages present" | sed 's/^/    /' | tail -n 25
  echo "[readme] $n: command $c exit $rc: $wall s wall, $cpu CPU s"
  [ "$rc" = 0 ] || { tail -n 30 "$work/command$n.log"; exit "$rc"; }
done
echo "[readme] all $n commands passed"
