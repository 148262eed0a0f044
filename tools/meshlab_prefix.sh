#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes a private MeshLab 2020.09 prefix that loads extra plugins, without root:
#   tools/meshlab_prefix.sh PREFIX PLUGIN.so [PLUGIN.so ...]
# MeshLab looks for plugins only in <dir of its binary>/../lib/x86_64-linux-gnu/meshlab/plugins,
# so the prefix gets real copies of /usr/bin/meshlab and /usr/bin/meshlabserver, links to the
# system's libmeshlab-common.so and plugins, and copies of the given plugins (plus the .mlx
# scripts found in a folder named after each plugin next to it). Run PREFIX/bin/meshlab or
# PREFIX/bin/meshlabserver afterwards.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 PREFIX PLUGIN.so [PLUGIN.so ...]" >&2; exit 2; }
prefix=$1; shift
sys=/usr/lib/x86_64-linux-gnu/meshlab
for b in meshlab meshlabserver; do
  [ -x "/usr/bin/$b" ] || { echo "$0: /usr/bin/$b not found: install Debian's meshlab package" >&2; exit 1; }
done
mkdir -p "$prefix/bin" "$prefix/lib/x86_64-linux-gnu/meshlab/plugins"
for b in meshlab meshlabserver; do
  cp -f "/usr/bin/$b" "$prefix/bin/$b"
done
ln -sf "$sys/libmeshlab-common.so" "$prefix/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so"
for p in "$sys"/plugins/*.so; do
  ln -sf "$p" "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/$(basename "$p")"
done
for p in "$@"; do
  [ -f "$p" ] || { echo "$0: plugin $p not found" >&2; exit 1; }
  name=$(basename "$p" .so)
  # replace (not write through) a link to an installed copy of the same plugin
  rm -f "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/$name.so"
  cp "$p" "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/"
  scripts="$(dirname "$p")/${name#lib}"
  if [ -d "$scripts" ]; then
    mkdir -p "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/${name#lib}"
    cp -f "$scripts"/*.mlx "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/${name#lib}/"
  fi
done
echo "MeshLab prefix ready: $prefix/bin/meshlab, $prefix/bin/meshlabserver"
