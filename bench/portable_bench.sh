#!/usr/bin/env bash
# Figures of the portable archives (docs/install.md): the compressed size of each archive (target
# <= 25 MB) and the time to load both plugins into a fresh pymeshlab harness process (target
# <= 0.5 s), side by side in one run:
#
#   bench/portable_bench.sh [BUILD_DIR] [RUNS]     (after tools/package.sh --portable all; default 7 runs)
#
# Load time: the wall time of `canonform_pymeshlabYYYY_harness --serve` answering two load_plugin
# requests (both plugins of the archive, extracted) and exiting, minus that of the same process
# answering none (process start, Qt and meshlab-common); medians over RUNS fresh processes, runs
# interleaved. The harness is pymeshlab's plugin loading (MeshLab's PluginManager::loadPlugin on the
# host's meshlab-common). Writes bench/results/portable.jsonl (one line per archive) and prints a table.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$(realpath "${1:-$here/build}")
runs=${2:-7}
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=$here/bench/results/portable.jsonl
mkdir -p "$(dirname "$out")"
: > "$out.tmp"
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
# wall seconds of one fresh harness process answering the requests on stdin
serve() { local h=$1 t0 t1; t0=$(date +%s.%N); "$h" --serve < "$2" > "$work/answer" 2>/dev/null; t1=$(date +%s.%N); echo "$t1 - $t0" | bc; }

printf '%-18s %10s %8s %12s %12s %12s\n' host "size (MB)" bundled "start (s)" "start+load" "load (s)"
for h in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7 meshlab2025.07; do
  a=$build/portable/canonform-plugins-$version-$h-linux-x86_64.tar.gz
  [ -f "$a" ] || { echo "no $a: run tools/package.sh --portable all first" >&2; exit 1; }
  size=$(stat -c %s "$a")
  tar -xzf "$a" -C "$work"
  d=$work/canonform-plugins-$version-$h-linux-x86_64
  bundled=$(ls "$d/canonform.libs" 2>/dev/null | wc -l)
  unpacked=$(du -sb "$d" | cut -f1)
  start=null load=null both=null
  case "$h" in
    pymeshlab2022.2) harness=$build/tests/canonform_pymeshlab2022_harness ;;
    pymeshlab2023.12) harness=$build/tests/canonform_pymeshlab2023_harness ;;
    pymeshlab2025.7) harness=$build/tests/canonform_pymeshlab2025_harness ;;
    *) harness="" ;;  # float: no harness on this machine (forky's MeshLab: tests/e2e/portable_test.sh)
  esac
  if [ -n "$harness" ]; then
    : > "$work/none"
    printf '{"op":"load_plugin","path":"%s"}\n{"op":"load_plugin","path":"%s"}\n' \
      "$d/libfilter_canonical.so" "$d/libfilter_viewdescriptor.so" > "$work/two"
    serve "$harness" "$work/two" > /dev/null  # warm the page cache
    grep -q error "$work/answer" && { echo "load_plugin failed: $(cat "$work/answer")" >&2; exit 1; }
    : > "$work/t_none"; : > "$work/t_two"
    for _ in $(seq "$runs"); do
      serve "$harness" "$work/none" >> "$work/t_none"
      serve "$harness" "$work/two" >> "$work/t_two"
    done
    start=$(median < "$work/t_none")
    both=$(median < "$work/t_two")
    load=$(echo "$both - $start" | bc | sed 's/^\./0./;s/^-\./-0./')
  fi
  printf '%-18s %10.2f %8d %12s %12s %12s\n' "$h" "$(echo "$size / 1000000" | bc -l)" "$bundled" "$start" "$both" "$load"
  printf '{"host": "%s", "archive_bytes": %d, "unpacked_bytes": %d, "bundled_libraries": %d, "runs": %d, "start_s": %s, "start_and_load_s": %s, "load_s": %s}\n' \
    "$h" "$size" "$unpacked" "$bundled" "$runs" "$start" "$both" "$load" >> "$out.tmp"
done
mv "$out.tmp" "$out"
echo "(medians of $runs fresh processes each; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); written to $out)"
