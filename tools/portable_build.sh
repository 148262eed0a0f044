#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The inside of `tools/package.sh --portable` and `--wheel`: runs in the Debian bullseye root
# filesystem (tools/host.sh bullseye). One CMake build of the four portable flavours
# (cmake/MeshLabPortable.cmake), the C API's shared library, the tool (without pictures or OpenCV)
# and the Python package, then one archive per HOST asked for, and the wheel for HOST `wheel`:
#
#   tools/portable_build.sh BUILD_DIR OUT_DIR COMMON_2022D COMMON_2025D COMMON_2025F HOST...
#
# COMMON_*: the libmeshlab-common.so each flavour links (2022.02d, 2025.07d, forky's float 2025.07).
# HOST: pymeshlab2022, pymeshlab2023, pymeshlab2025, meshlab2025, wheel. Each archive,
# OUT_DIR/canonform-plugins-VERSION-HOSTNAME-linux-x86_64.tar.gz, holds one folder of that name:
# both plugins, canonform.libs/ (tools/portable_bundle.py), scripts/ (the .mlx filter scripts) and
# INSTALL.txt. The archive's bytes depend only on its files (sorted, owner 0, time stamps of the
# newest plugin, gzip without name or time). The wheel, OUT_DIR/canonform-VERSION-py3-none-
# manylinux_2_31_x86_64.whl, holds the package, the library, the tool and the three pymeshlab
# flavours' plugins, with the archives' bundling (tools/wheel_build.py). Prints the paths made.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 6 ] || { echo "usage: $0 BUILD_DIR OUT_DIR COMMON_2022D COMMON_2025D COMMON_2025F HOST..." >&2; exit 2; }
build=$1 out=$2 c2022=$3 c2025=$4 c2025f=$5
shift 5
log() { printf '[portable] %s\n' "$*" >&2; }

flavours=(pymeshlab2022 pymeshlab2023 pymeshlab2025 meshlab2025)
targets=()
for f in "${flavours[@]}"; do targets+=("filter_canonical_$f" "filter_viewdescriptor_$f"); done
for host in "$@"; do
  [ "$host" = wheel ] && targets+=(canonform_c canonform canonform_python)
  # not archived: the runner the test portable.forky starts Debian forky's MeshLab 2025.07 with
  [ "$host" = meshlab2025 ] && targets+=(canonform-meshlab)
done
mkdir -p "$build" "$out"
build=$(realpath "$build") out=$(realpath "$out")
t0=$SECONDS
# --as-needed: a plugin names only the libraries it calls (not GLEW, GL or the Qt modules
# meshlab-common's interface lists). Neither FAISS (the plugins never train a codebook; the wheel's
# library and tool have no 'kmeans' codebooks) nor OpenCV (not on the plugins' path; the wheel
# leaves the `opencv` SIFT extractor, kept for comparison, out), nor Qt for the tool's pictures.
if ! { cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCANONFORM_PORTABLE=ON -DCANONFORM_BUILD_PLUGINS=OFF \
         -DCANONFORM_BUILD_TOOLS=ON -DCANONFORM_TOOL_PICTURES=OFF -DCANONFORM_WITHOUT_OPENCV=ON \
         -DCANONFORM_BUILD_TESTS=OFF -DCANONFORM_BUILD_BENCH=OFF -DCANONFORM_WITHOUT_FAISS=ON \
         -DCANONFORM_C_API=ON -DCANONFORM_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3 -DCANONFORM_DOCS_TESTS=OFF \
         -DCANONFORM_UNITY_BUILD=ON \
         -DCANONFORM_PORTABLE_COMMON_pymeshlab2022="$c2022" -DCANONFORM_PORTABLE_COMMON_pymeshlab2023="$c2025" \
         -DCANONFORM_PORTABLE_COMMON_pymeshlab2025="$c2025" -DCANONFORM_PORTABLE_COMMON_meshlab2025="$c2025f" \
         -DCMAKE_MODULE_LINKER_FLAGS=-Wl,--as-needed -DCMAKE_SHARED_LINKER_FLAGS=-Wl,--as-needed \
         -DCMAKE_EXE_LINKER_FLAGS=-Wl,--as-needed \
         ${CANONFORM_PORTABLE_CMAKE_ARGS:-} &&
       cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"; } > "$build/build.log" 2>&1; then
  grep -E -B2 -A8 "error|Error" "$build/build.log" | head -80 >&2
  log "build FAILED (log: $build/build.log)"
  exit 1
fi
log "${targets[*]} built in $((SECONDS - t0)) s ($(gcc -dumpfullversion), $(ldd --version | head -n 1 | awk '{print "glibc " $NF}'))"

version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
for host in "$@"; do
  if [ "$host" = wheel ]; then
    wheel=$out/canonform-$version-py3-none-manylinux_2_31_x86_64.whl
    inputs=("$build/src/libcanonform.so" "$build/apps/canonform" "$build/python/canonform" "$here/tools/wheel_build.py"
            "$here/tools/portable_bundle.py" "$0")
    for f in pymeshlab2022 pymeshlab2023 pymeshlab2025; do inputs+=("$build/portable/$f"); done
    if [ -f "$wheel" ] && [ -z "$(find "${inputs[@]}" "$here"/filter_*/scripts -newer "$wheel" 2>/dev/null | head -n 1)" ]; then
      echo "$wheel"
      continue
    fi
    log "the wheel: bundling"
    args=()
    for f in pymeshlab2022:pymeshlab2022.2 pymeshlab2023:pymeshlab2023.12 pymeshlab2025:pymeshlab2025.7; do
      args+=(--flavour "${f#*:}" "$build/portable/${f%%:*}/libfilter_canonical.so" "$build/portable/${f%%:*}/libfilter_viewdescriptor.so")
    done
    python3 "$here/tools/wheel_build.py" "$out" --package "$build/python/canonform" --tool "$build/apps/canonform" \
      --scripts "$here/filter_canonical/scripts" "$here/filter_viewdescriptor/scripts" "${args[@]}"
    continue
  fi
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
      load="MeshLab 2025.07 (AppImage, Flathub or Debian's package), single precision. Install (AppImage,
Debian):
  mkdir -p ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07
  tar -xzf $dir.tar.gz --strip-components=1 -C ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07
Flathub's MeshLab is sandboxed: use ~/.var/app/net.meshlab.MeshLab/data/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07
in both lines instead. Then start MeshLab: the five filters are in its Filters menu. The .mlx
filter scripts are in scripts/. (Help > Plugin Info > Load Plugins would copy the .so alone,
without canonform.libs/.)
Uninstall: rm -r ~/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/2025.07/{libfilter_canonical.so,libfilter_viewdescriptor.so,canonform.libs,scripts,INSTALL.txt}" ;;
    *)
      load="pymeshlab ${name#pymeshlab} (pip install pymeshlab==${name#pymeshlab}.*), double precision. (The
canonform wheel carries these plugins too: canonform.pymeshlab.load() loads them.) Use:
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
