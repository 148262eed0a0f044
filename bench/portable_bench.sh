#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Figures of the portable archives (docs/install.md): the compressed size of each archive (target
# <= 25 MB) and the time to load both plugins into a fresh pymeshlab harness process (target
# <= 0.5 s), side by side in one run:
#
#   bench/portable_bench.sh [BUILD_DIR] [RUNS]     (after tools/package.sh --portable all; default 7 runs)
#
# Load time: in a fresh `canonform_pymeshlabYYYY_harness --serve` process, the wall time of its two
# load_plugin calls (both plugins of the extracted archive: MeshLab's PluginManager::loadPlugin on
# the host's meshlab-common, as pymeshlab.load_plugin; dlopen of the plugins and their bundled
# libraries included), as the harness measures them (steady clock around each call); and the whole
# process's wall time (start, Qt, meshlab-common, the loads, exit). Medians over RUNS processes.
# Writes bench/results/portable.jsonl (one line per archive) and prints a table.
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

printf '%-18s %10s %8s %10s %12s\n' host "size (MB)" bundled "load (s)" "process (s)"
for h in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7 meshlab2025.07; do
  a=$build/portable/canonform-plugins-$version-$h-linux-x86_64.tar.gz
  [ -f "$a" ] || { echo "no $a: run tools/package.sh --portable all first" >&2; exit 1; }
  size=$(stat -c %s "$a")
  tar -xzf "$a" -C "$work"
  d=$work/canonform-plugins-$version-$h-linux-x86_64
  bundled=$(ls "$d/canonform.libs" 2>/dev/null | wc -l)
  unpacked=$(du -sb "$d" | cut -f1)
  load=null process=null
  case "$h" in
    pymeshlab2022.2) harness=$build/tests/canonform_pymeshlab2022_harness ;;
    pymeshlab2023.12) harness=$build/tests/canonform_pymeshlab2023_harness ;;
    pymeshlab2025.7) harness=$build/tests/canonform_pymeshlab2025_harness ;;
    *) harness="" ;;  # float: no harness on this machine (forky's MeshLab: tests/e2e/portable_test.sh)
  esac
  if [ -n "$harness" ]; then
    printf '{"op":"load_plugin","path":"%s"}\n{"op":"load_plugin","path":"%s"}\n' \
      "$d/libfilter_canonical.so" "$d/libfilter_viewdescriptor.so" > "$work/two"
    : > "$work/t_load"; : > "$work/t_process"
    for _ in $(seq "$runs"); do
      serve "$harness" "$work/two" >> "$work/t_process"
      grep -q error "$work/answer" && { echo "load_plugin failed: $(cat "$work/answer")" >&2; exit 1; }
      /usr/bin/python3 -c "import json,sys; print(round(sum(json.loads(l)['seconds'] for l in open(sys.argv[1])), 4))" \
        "$work/answer" >> "$work/t_load"
    done
    load=$(median < "$work/t_load")
    process=$(median < "$work/t_process")
  fi
  printf '%-18s %10.2f %8d %10s %12s\n' "$h" "$(echo "$size / 1000000" | bc -l)" "$bundled" "$load" "$process"
  printf '{"host": "%s", "archive_bytes": %d, "unpacked_bytes": %d, "bundled_libraries": %d, "runs": %d, "load_s": %s, "process_s": %s}\n' \
    "$h" "$size" "$unpacked" "$bundled" "$runs" "$load" "$process" >> "$out.tmp"
done
mv "$out.tmp" "$out"
echo "(medians of $runs fresh processes each; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); written to $out)"
