#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The portable archives (tools/package.sh --portable, built in Debian bullseye) on a Linux they were
# not built on: Debian forky as `apt install meshlab` leaves it (tools/host.sh forky-bare: newer
# glibc, GCC and Qt, and none of the libraries the archives bundle).
#  (a) forky's own MeshLab 2025.07 (float) loads the meshlab2025.07 archive through
#      canonform-meshlab (the portable build's, linked against forky's libmeshlab-common.so) and
#      runs all five filters; it refuses the pymeshlab archives' plugins with MeshLab's precision
#      message.
#  (b) For pymeshlab 2022.2, 2023.12 and 2025.7: a double meshlab-common of that release, compiled on
#      bookworm (2023.12: MeshLab 2025.07's source as "2023.12d", cmake/MeshLabFromSource.cmake
#      ALSO_AS) is copied in with the pymeshlab harness, laid out as pymeshlab's wheel lays itself
#      out (the module, lib/ next to it, RUNPATH $ORIGIN/lib), and the harness runs every filter of
#      that release's archive and refuses the other archives' plugins with MeshLab's messages.
# Each archive's bundled libraries are the ones the process loads (LD_DEBUG), and the results
# equal those of today's builds to 1e-6 relative (tests/portable_compare.py): the bookworm build's
# plugins in its harness for 2022.2 and 2025.7 (and 2025.7's for the 2023.12 stand-in), FLOAT_HOST's
# packaged plugins (tools/host.sh: trixie's MeshLab 2022.02 or forky's 2025.07, both float) through
# its canonform-meshlab for the float archive.
#   portable_test.sh SOURCE_DIR BUILD_DIR CANONFORM WORKDIR [FLOAT_HOST (default trixie)]
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); work=$4 float_host=${5:-trixie}
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
bare() { "$src/tools/host.sh" forky-bare "$@"; }
today() { CANONFORM_HOST_PREPARE=0 "$src/tools/host.sh" "$float_host" "$@"; }
archive() { echo "$build/portable/canonform-plugins-$version-$1-linux-x86_64.tar.gz"; }

echo "the portable archives in Debian forky with only MeshLab installed"
declare -A dir
for h in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7 meshlab2025.07; do
  tar -xzf "$(archive $h)" -C "$work"
  dir[$h]=$work/canonform-plugins-$version-$h-linux-x86_64
done

# The system has none of the libraries the archives bundle -------------------------------------------
bare ldconfig -p > ldconfig.txt 2>&1
bare bash -c '. /etc/os-release; echo "$PRETTY_NAME, glibc $(ldd --version | head -n 1 | awk "{print \$NF}")"' > system.txt 2>&1
bare dpkg-query -W meshlab libqt5core5t64 2>/dev/null | tr '\t\n' '  ' >> system.txt
originals=$(for d in "${dir[@]}"; do ls "$d/canonform.libs" 2>/dev/null; done | sed -E 's/-[0-9a-f]{8}(\.so)/\1/' | sort -u)
present=$(for o in $originals; do grep -q "^[[:space:]]$o " ldconfig.txt && echo "$o"; done)
# what a MeshLab process there loads anyway (MeshLab's own dependencies and its plugins')
bare bash -c 'ldd /usr/bin/meshlab /usr/lib/x86_64-linux-gnu/meshlab/*.so /usr/lib/x86_64-linux-gnu/meshlab/plugins/*.so' \
  2>/dev/null | awk '/=>/ {print $1}' | sort -u > meshlab_loads.txt
missing_there=$(for o in $present; do grep -qx "$o" meshlab_loads.txt || echo "$o"; done)
echo "    $(cat system.txt)"
echo "    bundled: $(echo $originals)"
echo "    of these, forky-bare has only what its MeshLab itself loads: ${present:-none}" | tr '\n' ' '; echo
check "forky-bare's ldconfig -p shows none of the bundled libraries but those MeshLab loads anyway${missing_there:+ (it also has: $(echo $missing_there))}" \
  test -z "$missing_there"

# (b) pymeshlab 2022.2, 2023.12, 2025.7: the harness and a meshlab-common compiled on bookworm --------
"$cf" generate fig.ply --vertices 2500 --pose 4 > /dev/null
"$cf" codebook cb.bin fig.ply --words 100 > /dev/null 2>&1
# wheel HARNESS MESHLAB_COMMON DEST: the harness as pymeshlab's wheel lays itself out, with the
# libraries forky-bare lacks (bookworm's TBB, GLEW and what they need in turn, ... that the
# harness itself links) in DEST/lib, each with RUNPATH $ORIGIN as auditwheel gives a wheel's
# libraries (a RUNPATH does not reach a library's own dependencies, so each needs its own)
wheel() {
  local harness=$1 common=$2 dest=$3 lib round missing
  mkdir -p "$dest/lib"
  cp "$harness" "$dest/harness"
  cp "$common" "$dest/lib/libmeshlab-common.so"
  for round in 1 2 3 4 5; do
    "$src/tools/host.sh" bullseye bash -c 'patchelf --set-rpath "\$ORIGIN/lib" "$1/harness" &&
                                           for l in "$1"/lib/*.so*; do patchelf --set-rpath "\$ORIGIN" "$l"; done' rpath "$dest" >/dev/null 2>&1
    missing=$(bare bash -c "cd '$dest' && ldd harness lib/*.so*" 2>/dev/null | awk '/not found/ {print $1}' | sort -u)
    [ -n "$missing" ] || break
    for lib in $missing; do
      cp -L "$(/sbin/ldconfig -p | awk -v l="$lib" '$1 == l && /x86-64/ {print $NF; exit}')" "$dest/lib/"
    done
  done
}
declare -A harness=([pymeshlab2022.2]=pymeshlab2022 [pymeshlab2023.12]=pymeshlab2023 [pymeshlab2025.7]=pymeshlab2025)
for h in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7; do
  f=${harness[$h]}
  wheel "$build/tests/canonform_${f}_harness" "$build/$f/lib/libmeshlab-common.so" "$work/wheel-$f"
  echo "    $h: harness + bookworm's meshlab-common $(strings "$build/$f/lib/libmeshlab-common.so" | grep -m1 -oE '20[0-9]{2}\.[0-9]{2}d' || true), lib/: $(ls "$work/wheel-$f/lib" | tr '\n' ' ')"
  others=()
  for o in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7; do
    [ "$o" = "$h" ] || others+=(--wrong-version "${dir[$o]}/libfilter_canonical.so")
  done
  bare env LD_DEBUG=files LD_DEBUG_OUTPUT="$work/$h.ld" "$work/wheel-$f/harness" \
    --plugin "${dir[$h]}/libfilter_canonical.so" --plugin "${dir[$h]}/libfilter_viewdescriptor.so" \
    --wrong-precision "${dir[meshlab2025.07]}/libfilter_canonical.so" "${others[@]}" \
    --vertices 2500 --pose 4 --codebook "$work/cb.bin" --out "$work/$h" > "$h.log" 2>&1
  grep -E "^  (FAIL|load_plugin)" "$h.log" | sed 's/^/    /' | cut -c1-220
  check "$h archive in forky: the harness (bookworm's $f meshlab-common) runs every filter: $(tail -n 1 "$h.log")" \
    grep -q ' 0 failed$' "$h.log"
  check "$h refuses the other two releases' plugins: 'has different version from the running MeshLab version'" \
    test "$(grep -c "has different version from the running MeshLab version" "$h.log")" -ge 2
  loaded=$(cat "$work/$h.ld".* 2>/dev/null | grep -oE "calling init: [^ ]*canonform\.libs/[^ ]*" | sed 's|.*/||' | sort -u)
  expect=$(ls "${dir[$h]}/canonform.libs" 2>/dev/null | sort)
  check "$h: the process loaded each bundled library from the archive ($(echo "$expect" | wc -w) of them)" \
    test "$loaded" = "$expect"
done

# today's builds on bookworm: the same harness runs with the bookworm build's plugins
for f in pymeshlab2022 pymeshlab2025; do
  "$build/tests/canonform_${f}_harness" --plugin "$build/$f/plugins/libfilter_canonical.so" \
    --plugin "$build/$f/plugins/libfilter_viewdescriptor.so" --vertices 2500 --pose 4 --codebook "$work/cb.bin" \
    --out "$work/today-$f" > "today-$f.log" 2>&1
  check "today's $f build (bookworm) in its harness: $(tail -n 1 "today-$f.log")" grep -q ' 0 failed$' "today-$f.log"
done
declare -A today=([pymeshlab2022.2]=today-pymeshlab2022 [pymeshlab2023.12]=today-pymeshlab2025 [pymeshlab2025.7]=today-pymeshlab2025)
for h in pymeshlab2022.2 pymeshlab2023.12 pymeshlab2025.7; do
  t=${today[$h]}
  /usr/bin/python3 "$src/tests/portable_compare.py" --rel 1e-6 "$t/outputs.json:$h/outputs.json" "$t/cf.ply:$h/cf.ply" \
    "$t/canon.ply:$h/canon.ply" "$t/descriptor.cfvd:$h/descriptor.cfvd" > "compare-$h.txt" 2>&1
  sed 's/^/  /' "compare-$h.txt" | grep -v "passed,"
  check "$h archive's results = today's ${t#today-} build's to 1e-6 relative ($(tail -n 1 "compare-$h.txt"))" \
    grep -q ' 0 failed$' "compare-$h.txt"
done

# (a) MeshLab 2025.07 (float): forky's packaged MeshLab through canonform-meshlab ------------------------
runner=$build/portable/build/apps/canonform-meshlab/canonform-meshlab
d=${dir[meshlab2025.07]}
plugins=(--plugin "$d/libfilter_canonical.so" --plugin "$d/libfilter_viewdescriptor.so")
declare -A params=(
  [cf]="--filter compute_conformal_factor"
  [fp]="--filter compute_feature_points --param fill=random --param seed=3"
  [ecf]="--filter generate_euclidean_canonical_form"
  [geo]="--filter generate_geodesic_canonical_form --param method=classical"
  [dv]="--filter compute_depth_view_descriptor --param codebook_file=$work/cb.bin --param seed=0")
for k in cf fp ecf geo dv; do
  extra=()
  [ "$k" = dv ] && extra=(--param "output_file=$work/archive_dv.cfvd")
  # shellcheck disable=SC2086
  bare env LD_DEBUG=files LD_DEBUG_OUTPUT="$work/float_$k.ld" "$runner" fig.ply "archive_$k.ply" ${params[$k]} "${extra[@]}" \
    "${plugins[@]}" --json "archive_$k.json" > "archive_$k.out" 2> "archive_$k.log"
  rc=$?
  check "MeshLab 2025.07 (forky's package) + the meshlab2025.07 archive: ${params[$k]%% --param*} exit 0 ($(head -c 150 "archive_$k.json" 2>/dev/null))" \
    test "$rc" -eq 0 -a -s "archive_$k.ply"
  [ "$k" = dv ] && extra=(--param "output_file=$work/today_dv.cfvd")
  # shellcheck disable=SC2086
  today canonform-meshlab fig.ply "today_$k.ply" ${params[$k]} "${extra[@]}" --json "today_$k.json" > /dev/null 2> "today_$k.log"
done
loaded=$(cat "$work"/float_*.ld.* 2>/dev/null | grep -oE "calling init: [^ ]*canonform\.libs/[^ ]*" | sed 's|.*/||' | sort -u)
check "meshlab2025.07: MeshLab loaded each bundled library from the archive" test "$loaded" = "$(ls "$d/canonform.libs" 2>/dev/null | sort)"
for w in pymeshlab2025.7 pymeshlab2022.2; do
  bare "$runner" fig.ply x.ply --filter compute_conformal_factor --plugin "${dir[$w]}/libfilter_canonical.so" > /dev/null 2> "refuse-$w.log"
  check "MeshLab 2025.07 refuses the $w archive's plugin: 'has different floating point precision'" \
    grep -q "libfilter_canonical.so has different floating point precision from the running MeshLab version" "refuse-$w.log"
done
pairs=()
for k in cf fp ecf geo dv; do pairs+=("today_$k.json:archive_$k.json" "today_$k.ply:archive_$k.ply"); done
/usr/bin/python3 "$src/tests/portable_compare.py" --rel 1e-6 "${pairs[@]}" today_dv.cfvd:archive_dv.cfvd > compare-float.txt 2>&1
sed 's/^/  /' compare-float.txt | grep -v "passed,"
check "meshlab2025.07 archive's results = $float_host's packaged build's to 1e-6 relative ($(tail -n 1 compare-float.txt))" \
  grep -q ' 0 failed$' compare-float.txt
finish
