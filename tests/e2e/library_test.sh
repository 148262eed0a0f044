#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The library as another project uses it (docs/library.md): the core alone (io, numerics, surface,
# canonical; -DCANONFORM_PLUGINS=OFF -DCANONFORM_VIEWS=OFF -DCANONFORM_RETRIEVAL=OFF, without oneTBB)
# configured and built from this source tree, installed with cmake --install, then the project in
# tests/find_package (find_package(canonform)) built against the install and run: its canonical
# forms must be byte for byte those of the canonform tool of the whole build. Then libcanonform-dev
# (tools/package.sh --dev) of the whole build, unpacked (not installed): its files, and the same
# project built against it.
#   library_test.sh SOURCE_DIR BUILD_DIR CANONFORM WORKDIR
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); work=$4
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)
jobs=$(nproc)

echo "the core library alone, installed, used by another project"
# In CMake's unity batches (CMAKE_UNITY_BUILD, a switch any user may set): the test is about
# configuring, installing and finding the package, and the batches cost less CPU (docs/testing.md).
# The forms below are still compared with the tool's byte for byte.
cmake -S "$src" -B core -DCMAKE_BUILD_TYPE=Release -DCANONFORM_PLUGINS=OFF -DCANONFORM_VIEWS=OFF \
  -DCANONFORM_RETRIEVAL=OFF -DCANONFORM_WITHOUT_TBB=ON -DCANONFORM_MESHLAB2022=OFF -DCANONFORM_MESHLAB2025=OFF \
  -DCANONFORM_HOSTS=OFF -DCMAKE_UNITY_BUILD=ON -DCMAKE_INSTALL_PREFIX="$work/prefix" > core_configure.log 2>&1
check "core configures with -DCANONFORM_PLUGINS=OFF -DCANONFORM_VIEWS=OFF -DCANONFORM_RETRIEVAL=OFF" test $? -eq 0
# Nothing but Eigen was looked for: no MeshLab tree, OpenCV, FAISS,
# VLFeat, OpenMP, oneTBB, nlohmann-json or Qt in the cache.
check "core's configuration looked for no MeshLab, OpenCV, FAISS, VLFeat, OpenMP, TBB, JSON or Qt" \
  bash -c "! grep -Eiq '^(OpenCV_DIR|faiss_DIR|VLFEAT_|OpenMP_|TBB_DIR|nlohmann_json_DIR|Qt5_DIR|CANONFORM_VCGLIB_DIR|MESHLAB)' core/CMakeCache.txt"
cmake --build core -j"$jobs" > core_build.log 2>&1
check "core builds" test $? -eq 0
cmake --install core --prefix "$work/prefix" > core_install.log 2>&1
check "cmake --install: headers, libraries, CMake package, the C API (header and shared library)" \
  test -f prefix/lib/cmake/canonform/canonformConfig.cmake -a -f prefix/include/canonform/canonical/method_registry.h \
       -a -f prefix/lib/libcanonform_canonical.a -a -f prefix/include/canonform/c_api/canonform.h -a -f prefix/lib/libcanonform.so
check "the C API installs its one public header (not its internal ones)" \
  bash -c "[ \"\$(ls prefix/include/canonform/c_api)\" = canonform.h ]"
check "no MeshLab glue, views or retrieval installed" \
  bash -c "[ ! -e prefix/include/canonform/meshlab ] && [ ! -e prefix/include/canonform/views ] && [ ! -e prefix/lib/libcanonform_views.a ]"

cmake -S "$src/tests/find_package" -B consumer -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" \
  > consumer_configure.log 2>&1 && cmake --build consumer -j"$jobs" > consumer_build.log 2>&1
check "a project with find_package(canonform COMPONENTS canonical io c_api) builds against the install (C++ and C)" \
  test -x consumer/consumer -a -x consumer/c_consumer

"$cf" generate fig.ply --vertices 2000 --pose 3
"$cf" simplify fig.ply fig500.ply --vertices 500 2>/dev/null
for m in "euclidean-N" "euclidean-A beta=20 seed=4" "geodesic-classical"; do
  set -- $m
  name=$1; shift
  mesh=fig.ply; [ "$name" = geodesic-classical ] && mesh=fig500.ply
  opts=(); for kv in "$@"; do opts+=("--${kv%%=*}" "${kv#*=}"); done
  consumer/consumer "$mesh" "lib_$name.ply" "$name" "$@" > "lib_$name.log" 2>&1
  "$cf" canonical "$mesh" "tool_$name.ply" --method "$name" "${opts[@]}" --quiet
  check "$name $*: the installed core's form is the whole build's, byte for byte (cmp)" cmp "lib_$name.ply" "tool_$name.ply"
  consumer/c_consumer "$mesh" "c_$name.ply" "$name" "$@" > "c_$name.log" 2>&1
  check "$name $*: ... and the installed C API's, from C (cmp)" cmp "c_$name.ply" "tool_$name.ply"
done
check "the core's C API says its retrieval area is not in this build" grep -q "retrieval area: not in this build" c_euclidean-N.log
check "the consumer also calls euclidean_canonical_form() directly" grep -q "direct call: 5 iterations" lib_euclidean-N.log

deb=$("$src/tools/package.sh" --dev --build-dir "$build" 2> package.log)
check "tools/package.sh --dev wrote $(basename "${deb:-none}")" test -f "$deb"
dpkg-deb -c "$deb" | awk '{print $6}' > dev_contents.txt
dpkg-deb -f "$deb" Depends > dev_depends.txt
check "libcanonform-dev holds headers, the libraries of every area and the CMake package" \
  bash -c "grep -q './usr/include/canonform/canonical/euclidean_canonical_form.h' dev_contents.txt &&
           grep -q './usr/include/canonform/views/view_descriptor.h' dev_contents.txt &&
           ! grep -q './usr/include/canonform/meshlab/' dev_contents.txt &&
           for a in common numerics surface canonical io procedural views retrieval; do grep -q \"./usr/lib/libcanonform_\$a.a\" dev_contents.txt || exit 1; done &&
           grep -q './usr/lib/cmake/canonform/canonformConfig.cmake' dev_contents.txt &&
           grep -q './usr/include/canonform/c_api/canonform.h' dev_contents.txt && grep -q './usr/lib/libcanonform.so' dev_contents.txt"
check "libcanonform-dev depends on the -dev packages ($(cat dev_depends.txt))" \
  bash -c "grep -q libeigen3-dev dev_depends.txt && grep -q libopencv-dev dev_depends.txt"
dpkg-deb -x "$deb" dev_root
cmake -S "$src/tests/find_package" -B consumer_deb -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/dev_root/usr" \
  > consumer_deb_configure.log 2>&1 && cmake --build consumer_deb -j"$jobs" > consumer_deb_build.log 2>&1
check "the project builds against the unpacked libcanonform-dev (views and retrieval found too)" test -x consumer_deb/consumer
consumer_deb/consumer fig.ply deb_euclidean-N.ply euclidean-N > /dev/null 2>&1
check "... and its form is the tool's (cmp)" cmp deb_euclidean-N.ply tool_euclidean-N.ply
LD_LIBRARY_PATH=$work/dev_root/usr/lib consumer_deb/c_consumer fig.ply deb_c_euclidean-N.ply euclidean-N > deb_c.log 2>&1
check "... and the C API's from C, whose retrieval area is in that build (cmp)" \
  bash -c "cmp deb_c_euclidean-N.ply tool_euclidean-N.ply && grep -q 'retrieval area: in this build' deb_c.log"
finish
