#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Refreshes the fuzz corpora kept in the repository (tests/fuzz/corpus/NAME/, one per libFuzzer
# target; tests/fuzz/run_fuzz.sh starts every run from them): each target runs for SECONDS more
# from the kept corpus, its build's working corpus and the unit tests' seeds, then everything is
# minimised with libFuzzer's -merge=1 (the smallest inputs that keep every feature seen) into a new
# corpus of inputs of at most MAX_LEN bytes (default 16384; the mesh corpora are kept at 2048:
# small meshes reach the same code, and the repository stays small), which replaces the kept one.
# Commit the result.
#
#   tools/fuzz_corpus.sh [--seconds S] [--max-len BYTES] [--only NAME] [BUILD_DIR]
#
# BUILD_DIR: a fuzz build (default build-san, made by tools/sanitizer_tests.sh, whose ctest run
# also writes the seeds). Prints the files and bytes of each corpus before and after.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=60 max_len=16384 only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --max-len) max_len=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    -*) echo "usage: $0 [--seconds S] [--max-len BYTES] [--only NAME] [BUILD_DIR]" >&2; exit 2 ;;
    *) break ;;
  esac
done
build=$(realpath "${1:-$here/build-san}")
[ -d "$build/tests/fuzz" ] || { echo "no fuzz build in $build (run tools/sanitizer_tests.sh first)" >&2; exit 1; }
size() { [ -d "$1" ] && echo "$(ls "$1" | wc -l) files, $(du -sb "$1" | cut -f1) bytes" || echo "none"; }
for target in "$build"/tests/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  name=$(basename "$target"); name=${name#fuzz_}
  [ -z "$only" ] || [ "$only" = "$name" ] || continue
  kept=$here/tests/fuzz/corpus/$name
  work=$build/fuzz/corpus/$name seeds=$build/fuzz/seeds/$name
  mkdir -p "$kept" "$work" "$seeds"
  before=$(size "$kept")
  if [ "$seconds" -gt 0 ]; then
    "$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 \
      "$work" "$seeds" "$kept" > "$build/fuzz/corpus_$name.log" 2>&1 ||
      { echo "$name: a finding (see $build/fuzz/corpus_$name.log); corpus not refreshed" >&2; exit 1; }
  fi
  new=$(mktemp -d)
  "$target" -merge=1 -timeout=20 -rss_limit_mb=2048 -max_len="$max_len" "$new" "$kept" "$work" "$seeds" \
    > "$build/fuzz/merge_$name.log" 2>&1
  rm -rf "$kept"; mkdir -p "$kept"
  # Content-addressed names (libFuzzer's own: the SHA-1 of the input), so a refresh is a clean diff.
  cp "$new"/* "$kept"/ 2>/dev/null || true
  rm -rf "$new"
  echo "$name: before $before; after $(size "$kept")"
done
