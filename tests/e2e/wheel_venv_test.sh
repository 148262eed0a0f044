#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The same wheel file where Python users are: a fresh venv in each RELEASE given - Debian bullseye
# (CPython 3.9, glibc 2.31: the oldest system the wheel is for), bookworm (3.11), trixie (3.13),
# forky (3.14); all four when none is given - each with its own numpy and no compiler
# (tools/host.sh RELEASE-python), by tests/e2e/wheel_inside.sh: pip install --no-index, import, the
# console command, the examples, the smoke tests. With bookworm among them, every output each other
# release wrote (the tool's and the module's forms, SIFT features, histograms, distance matrices,
# the retrieval example's distances) must equal bookworm's byte for byte. Prints each release's wall
# and CPU seconds; the releases run side by side. Needs root (the root filesystems).
# ctest: wheel.venv runs bullseye alone, wheel.releases (CANONFORM_WHEEL_RELEASES=ON) the four.
#   wheel_venv_test.sh SOURCE_DIR WHEEL WORKDIR [RELEASE...]
set -u
src=$(realpath "$1"); wheel=$(realpath "$2"); work=$3; shift 3
releases=("$@"); [ ${#releases[@]} -gt 0 ] || releases=(bullseye bookworm trixie forky)
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; work=$(realpath "$work")
# The releases side by side (their root filesystems are made, the first time, mostly by download
# and unpacking), then each one's log in order.
for r in "${releases[@]}"; do
  /usr/bin/time -f "%e %U %S" -o "$work/$r.time" "$src/tools/host.sh" "$r-python" \
    bash "$src/tests/e2e/wheel_inside.sh" "$src" "$wheel" "$work/$r" > "$work/$r.log" 2>&1 &
done
wait
for r in "${releases[@]}"; do
  echo "$r:"
  sed 's/^/  /' "$work/$r.log" | grep -v '^  \[host' | tail -n 30
  read -r wall user sys < <(tail -n 1 "$work/$r.time")
  check "$r: every check passed ($wall s wall, $(echo "$user + $sys" | bc) s CPU)" grep -q "^[0-9]* passed, 0 failed$" "$work/$r.log"
done
if [[ " ${releases[*]} " == *" bookworm "* ]]; then
  for r in "${releases[@]}"; do
    [ "$r" = bookworm ] && continue
    differ=()
    for f in "$work/bookworm/results"/*; do
      cmp -s "$f" "$work/$r/results/$(basename "$f")" || differ+=("$(basename "$f")")
    done
    n=$(ls "$work/bookworm/results" | wc -l)
    check "$r's $n outputs equal bookworm's byte for byte${differ:+ (differ: ${differ[*]})}" test ${#differ[@]} -eq 0 -a "$n" -ge 10
  done
fi
finish
