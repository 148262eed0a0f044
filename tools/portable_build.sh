#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The inside of `tools/package.sh --portable`: runs in the Debian bullseye root filesystem
# (tools/host.sh bullseye). One CMake build of the four portable flavours (cmake/MeshLabPortable.cmake),
# then one archive per HOST asked for:
#
#   tools/portable_build.sh BUILD_DIR OUT_DIR COMMON_2022D COMMON_2025D COMMON_2025F HOST...
#
# COMMON_*: the libmeshlab-common.so each flavour links (2022.02d, 2025.07d, forky's float 2025.07).
# HOST: pymeshlab2022, pymeshlab2023, pymeshlab2025, meshlab2025. Each archive,
# OUT_DIR/canonform-plugins-VERSION-HOSTNAME-linux-x86_64.tar.gz, holds one folder of that name:
# both plugins, canonform.libs/ (tools/portable_bundle.py), scripts/ (the .mlx filter scripts) and
# INSTALL.txt. The archive's bytes depend only on its files (sorted, owner 0, time stamps of the
# newest plugin, gzip without name or time). Prints the archives' paths.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 6 ] || { echo "usage: $0 BUILD_DIR OUT_DIR COMMON_2022D COMMON_2025D COMMON_2025F HOST..." >&2; exit 2; }
build=$1 out=$2 c2022=$3 c2025=$4 c2025f=$5
shift 5
log() { printf '[portable] %s\n' "$*" >&2; }

flavours=(pymeshlab2022 pymeshlab2023 pymeshlab2025 meshlab2025)
targets=()
for f in "${flavours[@]}"; do targets+=("filter_canonical_$f" "filter_viewdescriptor_$f"); done
mkdir -p "$build" "$out"
build=$(realpath "$build") out=$(realpath "$out")
t0=$SECONDS
# --as-needed: a plugin names only the libraries it calls (not GLEW, GL or the Qt modules
# meshlab-common's interface lists). The plugins alone: neither FAISS (the plugins never train a
# codebook) nor OpenCV (not on the plugins' path).
if ! { cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCANONFORM_PORTABLE=ON -DCANONFORM_BUILD_PLUGINS=OFF \
         -DCANONFORM_BUILD_TOOLS=OFF -DCANONFORM_BUILD_TESTS=OFF -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_WITHOUT_FAISS=ON -DCANONFORM_WITHOUT_OPENCV=ON \
         -DCANONFORM_PYTHON=OFF -DCANONFORM_DOCS_TESTS=OFF \
         -DCANONFORM_PORTABLE_COMMON_pymeshlab2022="$c2022" -DCANONFORM_PORTABLE_COMMON_pymeshlab2023="$c2025" \
         -DCANONFORM_PORTABLE_COMMON_pymeshlab2025="$c2025" -DCANONFORM_PORTABLE_COMMON_meshlab2025="$c2025f" \
         -DCMAKE_MODULE_LINKER_FLAGS=-Wl,--as-needed -DCMAKE_SHARED_LINKER_FLAGS=-Wl,--as-needed \
         ${CANONFORM_PORTABLE_CMAKE_ARGS:-} &&
       cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"; } > "$build/build.log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$build/build.log" | head -80 >&2
  log "build FAILED (log: $build/build.log)"
  exit 1
fi
log "plugins of the four flavours built in $((SECONDS - t0)) s ($(gcc -dumpfullversion), $(ldd --version | head -n 1 | awk '{print "glibc " $NF}'))"

version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
for host in "$@"; do
  case "$host" in
    pymeshlab2022) name=pymeshlab2022.2 ;;
    pymeshlab2023) name=pymeshlab2023.12 ;;
    pymeshlab2025) name=pymeshlab2025.7 ;;
    meshlab2025) name=meshlab2025.07 ;;
    *) echo "$0: unknown host $host" >&2; exit 2 ;;
  esac
  dir=canonform-plugins-$version-$name-linux-x86_64
  tarball=$out/$dir.tar.gz
  plugins=("$build/portable/$host/libfilter_canonical.so" "$build/portable/$host/libfilter_viewdescriptor.so")
  # up to date: no plugin, script or packaging script newer than the archive
  if [ -f "$tarball" ] && [ -z "$(find "${plugins[@]}" "$here"/filter_*/scripts "$here/tools/portable_bundle.py" "$0" \
                                   -newer "$tarball" 2>/dev/null | head -n 1)" ]; then
    echo "$tarball"
    continue
  fi
  stage=$(mktemp -d "$out/.stage.XXXXXX")
  trap 'rm -rf "$stage"' EXIT
  log "$dir: bundling"
  python3 "$here/tools/portable_bundle.py" "$stage/$dir" "${plugins[@]}" >&2
  mkdir -p "$stage/$dir/scripts"
  cp "$here"/filter_canonical/scripts/*.mlx "$here"/filter_viewdescriptor/scripts/*.mlx "$stage/$dir/scripts/"
  case "$host" in
    meshlab2025)
      load="MeshLab 2025.07 (AppImage, Flathub or Debian's package), single precision. Install:
  mkdir -p ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07
  tar -xzf $dir.tar.gz --strip-components=1 -C ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07
then start MeshLab: the five filters are in its Filters menu. The .mlx filter scripts are in
scripts/. (Help > Plugin Info > Load Plugins would copy the .so alone, without canonform.libs/.)
Uninstall: rm -r ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07/{libfilter_canonical.so,libfilter_viewdescriptor.so,canonform.libs,scripts,INSTALL.txt}" ;;
    *)
      load="pymeshlab ${name#pymeshlab} (pip install pymeshlab==${name#pymeshlab}.*), double precision. Use:
  tar -xzf $dir.tar.gz
  import pymeshlab
  pymeshlab.load_plugin('$dir/libfilter_canonical.so')
  pymeshlab.load_plugin('$dir/libfilter_viewdescriptor.so')
  ms = pymeshlab.MeshSet(); ms.load_new_mesh('mesh.off')
  ms.apply_filter('generate_euclidean_canonical_form')
The .mlx scripts are in scripts/ (ms.load_filter_script(path); ms.apply_filter_script()).
Uninstall: rm -r $dir" ;;
  esac
  {
    echo "canonform $version: the filter plugins libfilter_canonical.so and libfilter_viewdescriptor.so for $load"
    echo
    echo "canonform.libs/ holds the libraries the plugins need beyond what MeshLab and pymeshlab load"
    echo "(libmeshlab-common.so, Qt 5, the C and C++ runtime), each renamed so that it never meets"
    echo "another copy of the same library in the process. Built on Debian bullseye (glibc 2.31)."
  } > "$stage/$dir/INSTALL.txt"
  epoch=$(stat -c %Y "${plugins[@]}" | sort -n | tail -n 1)
  find "$stage/$dir" -exec touch -h -d "@$epoch" {} +
  (cd "$stage" && tar --sort=name --owner=0 --group=0 --numeric-owner --mtime="@$epoch" -cf - "$dir" | gzip -n -9 > "$tarball.tmp")
  mv "$tarball.tmp" "$tarball"
  rm -rf "$stage"
  log "$tarball: $(du -k "$tarball" | cut -f1) KiB"
  echo "$tarball"
done
