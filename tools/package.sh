#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes the Debian package of the plugins for the installed MeshLab, from a build (tools/build.sh):
#   tools/package.sh [--build-dir DIR]      prints the path of the .deb it wrote (in DIR)
#   tools/package.sh --dev [--build-dir DIR]   libcanonform-dev instead (see dev_package below)
#
#   installed MeshLab         package                          contents
#   2020.09 (bookworm)        canonform-plugins-meshlab2020    both plugins + their meshlabserver scripts
#   2022.02 (trixie)          canonform-plugins-meshlab2022    both plugins + /usr/bin/canonform-meshlab
#   2025.07 (forky, sid)      canonform-plugins-meshlab2025    both plugins + /usr/bin/canonform-meshlab
#
# The plugins go where Debian's MeshLab looks for them, /usr/lib/x86_64-linux-gnu/meshlab/plugins.
# Install it with `apt install ./canonform-plugins-meshlabYYYY_VERSION_ARCH.deb`; MeshLab then shows
# the filters. Depends: that MeshLab release (the plugin manager accepts only its own version) and
# the libraries the plugins link, as dpkg-shlibdeps finds them. Made with cmake --install (component
# `plugins`) and dpkg-deb. The version is CMake's project() version (canonform --version); the
# licence (GPL-3.0-or-later) is in /usr/share/doc/PACKAGE/copyright.
#
# Portable archives, for the MeshLab and pymeshlab users install from elsewhere (docs/install.md):
#   tools/package.sh --portable HOST [--build-dir DIR]    prints the archive's path (in DIR/portable)
#
#   HOST            archive (canonform-plugins-VERSION-...-linux-x86_64.tar.gz)   for
#   pymeshlab2022   ...-pymeshlab2022.2-...                                         pymeshlab 2022.2.x (double)
#   pymeshlab2023   ...-pymeshlab2023.12-...                                        pymeshlab 2023.12.x (double)
#   pymeshlab2025   ...-pymeshlab2025.7-...                                         pymeshlab 2025.7.x (double)
#   meshlab2025     ...-meshlab2025.07-...                                          MeshLab 2025.07 (float: AppImage, Flathub, forky)
#   all             the four
#
# The wheel, for every Python 3 on any x86-64 Linux with glibc 2.31 or later (docs/install.md):
#   tools/package.sh --wheel [--build-dir DIR]     prints the wheel's path (in DIR/portable)
# canonform-VERSION-py3-none-manylinux_2_31_x86_64.whl: the Python package, the C API's library,
# the canonform tool (console script) and the pymeshlab 2022.2, 2023.12 and 2025.7 plugins, from the
# same bullseye build as the archives (nothing compiled twice; tools/wheel_build.py assembles it).
#
# Built in a Debian bullseye root filesystem (tools/host.sh bullseye: glibc 2.31, GCC 10, Qt 5.15.2)
# by tools/portable_build.sh, one CMake build (DIR/portable/build) for the four; the plugins link the
# double meshlab-common libraries of the bookworm build in DIR (build/pymeshlab2022/lib,
# build/pymeshlab2025/lib: tools/build.sh) and Debian forky's float one (from tools/host.sh
# forky-bare). Each archive carries the libraries the plugins need beyond the host's
# (tools/portable_bundle.py). Needs root (chroot).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
dev=0
portable=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    --dev) dev=1; shift ;;
    --portable) portable=$2; shift 2 ;;
    --wheel) portable=wheel; shift ;;
    *) echo "usage: $0 [--build-dir DIR] [--dev | --wheel | --portable pymeshlab2022|pymeshlab2023|pymeshlab2025|meshlab2025|all]" >&2; exit 2 ;;
  esac
done
die() { echo "$0: $*" >&2; exit 1; }
[ -f "$build/CMakeCache.txt" ] || die "no build in $build: run tools/build.sh first"
build=$(realpath "$build")

if [ -n "$portable" ]; then
  case "$portable" in
    all) hosts=(pymeshlab2022 pymeshlab2023 pymeshlab2025 meshlab2025) ;;
    pymeshlab2022|pymeshlab2023|pymeshlab2025|meshlab2025|wheel) hosts=("$portable") ;;
    *) die "unknown portable host '$portable' (pymeshlab2022, pymeshlab2023, pymeshlab2025, meshlab2025, all)" ;;
  esac
  [ "$(id -u)" -eq 0 ] || die "--portable and --wheel need root (the bullseye root filesystem: tools/host.sh)"
  # the double meshlab-common libraries of the bookworm build (2.5 CPU-minutes each when missing)
  for y in 2022 2025; do
    lib=$build/pymeshlab$y/lib/libmeshlab-common.so
    [ -f "$lib" ] && continue
    grep -q "^CANONFORM_MESHLAB$y:BOOL=ON" "$build/CMakeCache.txt" ||
      die "no $lib: build with CANONFORM_MESHLAB$y=1 tools/build.sh (bookworm) first"
    cmake --build "$build" -j"$(nproc)" --target "pymeshlab${y}_common" >&2
  done
  # MeshLab 2025.07's float libmeshlab-common.so, as Debian forky packages it
  mkdir -p "$build/portable/forky"
  forky_lib=$build/portable/forky/libmeshlab-common.so
  [ -f "$forky_lib" ] || "$here/tools/host.sh" forky-bare cp /usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so "$forky_lib" >&2
  exec "$here/tools/host.sh" bullseye "$here/tools/portable_build.sh" "$build/portable/build" "$build/portable" \
    "$build/pymeshlab2022/lib/libmeshlab-common.so" "$build/pymeshlab2025/lib/libmeshlab-common.so" "$forky_lib" "${hosts[@]}"
fi

# --- libcanonform-dev ---------------------------------------------------------------------------
# The library for other projects (docs/library.md): the headers, the static libraries of the areas
# the build has and the CMake package (find_package(canonform)), from cmake --install's component
# `dev`, under /usr. Depends: the -dev packages of what those areas link (Eigen; oneTBB
# where the build used it; OpenCV and FAISS for views (the `opencv` extractor, codebook training); nlohmann-json for retrieval).
dev_package() {
  local version arch name=libcanonform-dev stage root deb depends cache=$build/CMakeCache.txt
  version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$cache")
  arch=$(dpkg --print-architecture)
  [ -n "$version" ] || die "no project version in $cache"
  deb=$build/${name}_${version}_${arch}.deb
  stage=$(mktemp -d "$build/.package-dev.XXXXXX")
  trap 'rm -rf "$stage"' EXIT
  root=$stage/$name
  cmake --install "$build" --component dev --prefix "$root/usr" >/dev/null
  [ -f "$root/usr/lib/cmake/canonform/canonformConfig.cmake" ] || die "the build installs no CMake package (component dev)"
  depends="libeigen3-dev"
  [ -f "$root/usr/lib/libcanonform_views.a" ] && depends+=", libopencv-dev, libfaiss-dev"  # views_opencv, codebook_training
  [ -f "$root/usr/lib/libcanonform_retrieval.a" ] && depends+=", nlohmann-json3-dev"
  grep -q "CANONFORM_HAVE_TBB" "$root/usr/lib/cmake/canonform/canonformTargets.cmake" && depends+=", libtbb-dev"
  mkdir -p "$root/DEBIAN"
  {
    echo "Package: $name"
    echo "Version: $version"
    echo "Architecture: $arch"
    echo "Maintainer: canonform developers <canonform@localhost>"
    echo "Installed-Size: $(du -sk "$root/usr" | cut -f1)"
    echo "Depends: $depends"
    echo "Section: libdevel"
    echo "Priority: optional"
    echo "Description: canonical forms of non-rigid meshes - C++ library"
    echo " Headers, static libraries and the CMake package (find_package(canonform)) of canonform:"
    echo " Euclidean and geodesic canonical forms (Pickup et al. 2015), conformal factor, feature"
    echo " points, SMACOF and MDS, mesh files, and (where built) view descriptors and retrieval."
  } > "$root/DEBIAN/control"
  local epoch
  epoch=$(find "$root/usr" -type f -printf '%T@\n' | cut -d. -f1 | sort -n | tail -n 1)
  find "$root" -exec touch -h -d "@$epoch" {} +
  SOURCE_DATE_EPOCH=$epoch dpkg-deb --root-owner-group -Zxz --build "$root" "$deb.tmp" >/dev/null
  mv "$deb.tmp" "$deb"
  echo "$deb"
}
if [ "$dev" = 1 ]; then
  dev_package
  exit 0
fi
# --- the plugins' package -----------------------------------------------------------------------

ml=$("$here/tools/setup.sh" --meshlab)          # 2020.09, 2022.02 or 2025.07
series=${ml%%.*}                                # 2020, 2022, 2025
name=canonform-plugins-meshlab$series
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
arch=$(dpkg --print-architecture)
[ -n "$version" ] || die "no project version in $build/CMakeCache.txt"
# the next MeshLab release (2022.02 -> 2022.03): the plugin manager compares the version prefix
next="${ml%.*}.$(printf '%02d' $((10#${ml#*.} + 1)))"

deb=$build/${name}_${version}_${arch}.deb
# up to date: no built file newer than the package (dpkg-shlibdeps alone takes seconds)
inputs=("$build"/meshlab/plugins "$build"/apps/canonform-meshlab/canonform-meshlab "$0")
if [ -f "$deb" ] && [ -z "$(find "${inputs[@]}" -newer "$deb" 2>/dev/null | head -n 1)" ]; then
  echo "$deb"
  exit 0
fi

stage=$(mktemp -d "$build/.package.XXXXXX")
trap 'rm -rf "$stage"' EXIT
root=$stage/$name
cmake --install "$build" --component plugins --prefix "$root/usr" --strip >/dev/null
plugins=("$root"/usr/lib/x86_64-linux-gnu/meshlab/plugins/*.so)
[ -f "${plugins[0]}" ] || die "the build installs no plugin (component plugins)"
binaries=("${plugins[@]}")
[ -x "$root/usr/bin/canonform-meshlab" ] && binaries+=("$root/usr/bin/canonform-meshlab")

# shared-library dependencies (libmeshlab-common.so belongs to meshlab, named explicitly below)
mkdir -p "$stage/shlibs/debian"
touch "$stage/shlibs/debian/control"
shlibs=$(cd "$stage/shlibs" && dpkg-shlibdeps -O --ignore-missing-info -l/usr/lib/x86_64-linux-gnu/meshlab \
           "${binaries[@]}" 2>"$stage/shlibdeps.log") || { cat "$stage/shlibdeps.log" >&2; die "dpkg-shlibdeps failed"; }
shlibs=$(printf '%s\n' "$shlibs" | sed -n 's/^shlibs:Depends=//p')

# the licence, as Debian's machine-readable copyright file (the full text is Debian's own
# /usr/share/common-licenses/GPL-3, which LICENSE in the repository reproduces)
mkdir -p "$root/usr/share/doc/$name"
cat > "$root/usr/share/doc/$name/copyright" <<EOF
Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/
Upstream-Name: canonform
Upstream-Contact: canonform developers <canonform@localhost>

Files: *
Copyright: the canonform developers
License: GPL-3.0+

License: GPL-3.0+
 This program is free software: you can redistribute it and/or modify it under
 the terms of the GNU General Public License as published by the Free Software
 Foundation, either version 3 of the License, or (at your option) any later
 version. The plugins link MeshLab's libmeshlab-common, which is GPL-3.0 too.
 .
 This program is distributed in the hope that it will be useful, but WITHOUT ANY
 WARRANTY; without even the implied warranty of MERCHANTABILITY or FITNESS FOR A
 PARTICULAR PURPOSE. See the GNU General Public License for more details.
 .
 On Debian systems, the complete text of the GNU General Public License version 3
 can be found in '/usr/share/common-licenses/GPL-3'.
EOF

mkdir -p "$root/DEBIAN"
size=$(du -sk "$root/usr" | cut -f1)
{
  echo "Package: $name"
  echo "Version: $version"
  echo "Architecture: $arch"
  echo "Maintainer: canonform developers <canonform@localhost>"
  echo "Installed-Size: $size"
  echo "Depends: meshlab (>= $ml~), meshlab (<< $next~)${shlibs:+, $shlibs}"
  echo "Section: graphics"
  echo "Priority: optional"
  echo "Description: canonical forms of non-rigid meshes, as MeshLab $ml filter plugins"
  echo " Euclidean canonical forms (Pickup et al. 2015), the conformal factor, feature points,"
  echo " the geodesic canonical form and the depth view descriptor, as filters of MeshLab $ml"
  echo " (Filters menu; plugins libfilter_canonical.so and libfilter_viewdescriptor.so)."
  if [ -x "$root/usr/bin/canonform-meshlab" ]; then
    echo " canonform-meshlab applies them (or any MeshLab filter) headless:"
    echo " canonform-meshlab IN OUT --filter NAME [--param key=value]..."
  fi
} > "$root/DEBIAN/control"
# reproducible: every time stamp is that of the newest built file, so the same build gives the same bytes
epoch=$( (find "${inputs[@]}" -type f -printf '%T@\n' 2>/dev/null || true) | cut -d. -f1 | sort -n | tail -n 1)
find "$root" -exec touch -h -d "@$epoch" {} +
SOURCE_DATE_EPOCH=$epoch dpkg-deb --root-owner-group -Zxz --build "$root" "$deb.tmp" >/dev/null
mv "$deb.tmp" "$deb"
echo "$deb"
