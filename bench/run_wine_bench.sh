#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Windows build under Wine next to the Linux build, in one run (docs/windows.md): a sanity
# ratio, not a target. On the procedural figure of 10k vertices (pose 1):
#   canonical   `canonform canonical fig.ply out.ply` (variant N, defaults, --threads 1)
#   descriptor  `canonform descriptor fig.ply out.cfvd` (the 66 views and SIFT, no codebook)
# each build run alternately (Linux, Windows, Linux, ...) under /usr/bin/time: medians of RUNS of
# the wall and CPU (user + system) seconds of the whole process (for Windows: Wine's process, in
# which the program runs, after Wine's prefix is made; wineserver is not counted). Optional
# further Windows builds (NAME=PATH.exe: e.g. one configured otherwise)
# join the alternation. Writes bench/results/wine.jsonl (one line per build and task, with the
# machine's load) and prints a table.
#   bench/run_wine_bench.sh LINUX_CANONFORM CANONFORM.EXE [RUNS] [NAME=OTHER.exe...]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
lin=$(realpath "$1"); exe=$(realpath "$2"); runs=${3:-5}; shift 2; [ $# -gt 0 ] && shift
builds=("linux|$lin" "windows|$here/tools/wine.sh $exe")
for b in "$@"; do builds+=("${b%%=*}|$here/tools/wine.sh $(realpath "${b#*=}")"); done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=$here/bench/results/wine.jsonl
cd "$work"  # relative paths: canonform.exe (CLI11 on Windows) reads a leading '/' as an option's
"$lin" generate fig.ply --vertices 10000 --pose 1 > /dev/null
for b in "${builds[@]}"; do ${b#*|} --version > /dev/null; done  # Wine's prefix made before timing
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
load0=$(cut -d' ' -f1 /proc/loadavg)
for r in $(seq "$runs"); do
  for b in "${builds[@]}"; do
    name=${b%%|*}; cmd=${b#*|}
    /usr/bin/time -f "%e %U %S" -o "$work/t" $cmd canonical fig.ply "c_$name.ply" --threads 1 --quiet
    echo "$(cat "$work/t")" >> "$work/canonical_$name"
    /usr/bin/time -f "%e %U %S" -o "$work/t" $cmd descriptor fig.ply "d_$name.cfvd" > /dev/null
    echo "$(cat "$work/t")" >> "$work/descriptor_$name"
  done
done
load1=$(cut -d' ' -f1 /proc/loadavg)
same=2; cmp -s "$work/c_linux.ply" "$work/c_windows.ply" && same=1  # Linux's and Windows' forms
: > "$out.tmp"
printf '%-12s %-12s %10s %10s %12s\n' task build "wall (s)" "CPU (s)" "CPU / Linux"
for task in canonical descriptor; do
  lincpu=$(awk '{print $2 + $3}' "$work/${task}_linux" | median)
  for b in "${builds[@]}"; do
    name=${b%%|*}
    wall=$(awk '{print $1}' "$work/${task}_$name" | median)
    cpu=$(awk '{print $2 + $3}' "$work/${task}_$name" | median)
    ratio=$(echo "scale=3; $cpu / $lincpu" | bc)
    printf '%-12s %-12s %10s %10s %12s\n' "$task" "$name" "$wall" "$cpu" "$ratio"
    printf '{"task": "%s", "build": "%s", "vertices": 10000, "runs": %d, "wall_s": %s, "cpu_s": %s, "cpu_ratio_to_linux": %s, "load": [%s, %s], "same_form_as_linux": %s}\n' \
      "$task" "$name" "$runs" "$wall" "$cpu" "$ratio" "$load0" "$load1" \
      "$(cmp -s "$work/c_linux.ply" "$work/c_$name.ply" && echo true || echo false)" >> "$out.tmp"
  done
done
mv "$out.tmp" "$out"
echo "the Windows build's canonical form the same bits as Linux's: $([ "$same" = 1 ] && echo yes || echo no); load $load0 -> $load1; $out"
