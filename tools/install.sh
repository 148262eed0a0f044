#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the built plugins and the canonform tool.
#   tools/install.sh [--build-dir DIR]                 as root: plugins into MeshLab's plugin folder
#                                                      (/usr/lib/x86_64-linux-gnu/meshlab/plugins),
#                                                      canonform (and canonform-full) into /usr/local/bin
#   tools/install.sh --prefix DIR [--build-dir DIR]    without root: a private MeshLab prefix in DIR
#                                                      (DIR/bin/meshlab, DIR/bin/meshlabserver,
#                                                      DIR/bin/canonform, DIR/bin/canonform-full)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="$here/build"
prefix=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    --prefix) prefix=$2; shift 2 ;;
    *) echo "usage: $0 [--prefix DIR] [--build-dir DIR]" >&2; exit 2 ;;
  esac
done
plugins=("$build"/meshlab/plugins/*.so)
[ -f "${plugins[0]}" ] || { echo "$0: no plugins in $build/meshlab/plugins: build first (tools/build.sh)" >&2; exit 1; }
# the tool: canonform, and canonform-full where the build makes it (canonform runs it, from the same
# folder, for every command beyond its own: apps/canonform/main.cpp)
tool=("$build/apps/canonform")
[ -x "$build/apps/canonform-full" ] && tool+=("$build/apps/canonform-full")
if [ -z "$prefix" ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "$0: installing into MeshLab's plugin folder needs root; use --prefix DIR for a private install" >&2
    exit 1
  fi
  dest=/usr/lib/x86_64-linux-gnu/meshlab/plugins
  for p in "${plugins[@]}"; do
    install -m 0644 "$p" "$dest/"
    scripts="$build/meshlab/plugins/$(basename "$p" .so | sed 's/^lib//')"
    if [ -d "$scripts" ]; then install -d "$dest/$(basename "$scripts")"; install -m 0644 "$scripts"/*.mlx "$dest/$(basename "$scripts")/"; fi
  done
  install -m 0755 "${tool[@]}" /usr/local/bin/
  runner="$build/apps/canonform-meshlab/canonform-meshlab"  # MeshLab 2022.02 and later
  [ -x "$runner" ] && install -m 0755 "$runner" /usr/local/bin/canonform-meshlab
  echo "installed: ${plugins[*]##*/} into $dest; ${tool[*]##*/}$([ -x "$runner" ] && echo " and canonform-meshlab") into /usr/local/bin"
else
  "$here/tools/meshlab_prefix.sh" "$prefix" "${plugins[@]}"
  install -m 0755 "${tool[@]}" "$prefix/bin/"
  echo "installed: ${tool[*]##*/} into $prefix/bin"
fi
