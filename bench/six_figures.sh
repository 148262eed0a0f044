# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by the bench scripts: six_figures BUILD_DIR DIR writes six procedural figures of 10k
# vertices into DIR (the six body types, poses 1-6), the collection of the 600-mesh plan and the
# query benchmark. bench_jsonl BUILD_DIR OUT BENCH [ARGS...] runs BENCH on six fresh figures (in a
# temporary folder) with ARGS after them, and writes its JSON lines with the machine's load before
# and after to OUT (replaced only when the bench succeeds).
six_figures() {
  local build=$1 dir=$2 pose=1 c
  for c in standard long-arms short-legs long-tail stocky long-neck; do
    "$build/apps/canonform" generate "$dir/$c.ply" --vertices 10000 --pose $pose --class $c
    pose=$((pose + 1))
  done
}

bench_jsonl() {
  local build=$1 out=$2 bench=$3
  shift 3
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  six_figures "$build" "$work"
  {
    echo "{\"load_before\": \"$(cut -d' ' -f1-3 /proc/loadavg)\", \"cpus\": $(nproc), \"date\": \"$(date -u +%FT%TZ)\", \"cpu\": \"$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)\"}"
    "$bench" "$work"/*.ply "$@"
    echo "{\"load_after\": \"$(cut -d' ' -f1-3 /proc/loadavg)\"}"
  } | tee "$out.tmp"
  mv "$out.tmp" "$out"
}
