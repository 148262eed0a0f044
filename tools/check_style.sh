#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The style check of tools/run_tests.sh:
#  - every C and C++ source of the project (not external/) is as clang-format formats it with the
#    repository's .clang-format. Formatting differs between clang-format releases: the tree is
#    formatted with Debian bookworm's clang-format 14 (tools/setup.sh installs it there); with
#    another major version the check says so and is skipped. To format a file: clang-format -i FILE.
#  - commit subjects are at most 72 characters (detail goes in the body), for the commits made since
#    this check was added; a shallow clone without that commit skips it.
#   tools/check_style.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
rc=0

if ! command -v clang-format > /dev/null; then
  echo "[style] clang-format is not installed (tools/setup.sh installs it on bookworm): not checked"
else
  major=$(clang-format --version | sed -n 's/.*version \([0-9]*\).*/\1/p')
  if [ "$major" != 14 ]; then
    echo "[style] clang-format $major is not the release the tree is formatted with (14): not checked"
  else
    mapfile -t files < <(git ls-files '*.c' '*.cc' '*.cpp' '*.h' '*.hpp' ':!external/')
    if ! clang-format --dry-run -Werror "${files[@]}" 2> style.log.$$; then
      grep 'error:' style.log.$$ | cut -d: -f1 | sort | uniq -c | sed 's/^/[style] not formatted (lines): /' >&2
      echo "[style] FAILED: run clang-format -i on these files" >&2
      rc=1
    else
      echo "[style] ${#files[@]} C and C++ sources formatted as clang-format 14 formats them"
    fi
    rm -f style.log.$$
  fi
fi

# Subjects of the commits made since the check began (committed at or after its first commit: a
# branch merged later keeps the dates of its older commits).
since=$(git log --format=%H --diff-filter=A -- tools/check_style.sh | tail -1)
if [ -z "$since" ]; then
  echo "[style] the history of tools/check_style.sh is not in this clone: commit subjects not checked"
else
  long=$(git log --no-merges --since="@$(git log -1 --format=%ct "$since")" --format='%h %s' HEAD |
         awk '{ s = $0; sub(/^[^ ]* /, "", s); if (length(s) > 72) print }')
  if [ -n "$long" ]; then
    echo "[style] FAILED: commit subjects over 72 characters (put the detail in the body):" >&2
    echo "$long" >&2
    rc=1
  else
    echo "[style] commit subjects at most 72 characters since $(git log -1 --format=%h "$since")"
  fi
fi
exit "$rc"
