#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Two builds of the tool side by side, as whole processes: each case run RUNS times with the two
# binaries alternating, so both see the same machine. Per process: wall, user + system CPU seconds
# and peak RSS (/usr/bin/time); per case and build, one more process under `strace -f -c` counts
# the threads started (clone, clone3) and the sched_yield calls of spinning thread pools.
#   bench/run_side_by_side.sh OUT.jsonl RUNS OLD_LABEL OLD_BIN NEW_LABEL NEW_BIN CASE...
# CASE is "name:arguments of the tool" (split at spaces), e.g.
#   "canonical:canonical mesh.off /tmp/form.ply --quiet" "version:--version"
# OUT.jsonl: a header line (date, load, cores, the two labels), then one line per process
# ({"bench": "cli", "run": "CASE, BUILD", "case", "build", "wall_s", "cpu_s", "rss_mib"}) and per strace run
# ({"bench": "cli_syscalls", "case", "build", "threads_started", "sched_yield"}).
# With CANONFORM_PERF_STAT=1 each process also runs under `perf stat` (Debian's linux-perf), and its
# line gets "task_clock_ms" (CPU milliseconds, finer than /usr/bin/time's 10 ms) and "page_faults".
set -euo pipefail
[ $# -ge 7 ] || { sed -n 3,12p "$0" >&2; exit 2; }
out=$1 runs=$2 old_label=$3 old_bin=$4 new_label=$5 new_bin=$6
shift 6
for b in "$old_bin" "$new_bin"; do [ -x "$b" ] || { echo "not an executable: $b" >&2; exit 2; }; done
command -v strace > /dev/null || { echo "strace missing (Debian's strace)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
printf '{"date": "%s", "load_before": "%s", "cpus": %d, "cpu": "%s", "builds": ["%s", "%s"]}\n' \
  "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(nproc)" "$cpu" "$old_label" "$new_label" > "$out"
for case in "$@"; do
  name=${case%%:*}
  read -r -a args <<< "${case#*:}"
  for ((r = 0; r < runs; ++r)); do
    for pair in "$old_label=$old_bin" "$new_label=$new_bin"; do
      label=${pair%%=*} bin=${pair#*=}
      stat=()
      [ "${CANONFORM_PERF_STAT:-0}" = 1 ] && stat=(perf stat -x, -o "$tmp/perf" -e task-clock,page-faults --)
      "${stat[@]}" /usr/bin/time -f '%e %U %S %M' -o "$tmp/time" "$bin" "${args[@]}" > /dev/null 2> "$tmp/err" ||
        { echo "$label failed on $name:" >&2; cat "$tmp/err" >&2; exit 1; }
      read -r wall user sys rss < "$tmp/time"
      extra=""
      if [ ${#stat[@]} -gt 0 ]; then
        extra=$(awk -F, '$3 == "task-clock" { t = $1 } $3 == "page-faults" { f = $1 }
                         END { printf ", \"task_clock_ms\": %.1f, \"page_faults\": %d", t, f }' "$tmp/perf")
      fi
      printf '{"bench": "cli", "run": "%s, %s", "case": "%s", "build": "%s", "wall_s": %s, "cpu_s": %.2f, "rss_mib": %.1f%s}\n' \
        "$name" "$label" "$name" "$label" "$wall" "$(echo "$user + $sys" | bc)" "$(echo "$rss / 1024" | bc -l)" "$extra" >> "$out"
    done
  done
  for pair in "$old_label=$old_bin" "$new_label=$new_bin"; do
    label=${pair%%=*} bin=${pair#*=}
    strace -f -c -o "$tmp/strace" "$bin" "${args[@]}" > /dev/null 2>&1
    count() { awk -v s="$1" '$NF == s { n = $4 } END { print n + 0 }' "$tmp/strace"; }
    clones=$(( $(count clone) + $(count clone3) ))
    yields=$(count sched_yield)
    printf '{"bench": "cli_syscalls", "case": "%s", "build": "%s", "threads_started": %d, "sched_yield": %d}\n' \
      "$name" "$label" "$clones" "$yields" >> "$out"
  done
done
printf '{"load_after": "%s"}\n' "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$out"
echo "wrote $out" >&2
