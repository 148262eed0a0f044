#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# canonform.exe (the Windows build, under Wine) against this build's canonform (Linux), on the
# same inputs: every output the same bits (`cmp`; docs/install.md, "Windows"). Compared: the
# conformal factor, the feature points, the canonical form by every method of the registry, a
# codebook trained by the library's own k-means (lloyd; FAISS's is not in the Windows build), the
# depth-view descriptors, their distance matrix, evaluate's measures, and a small retrieval run
# (none and euclidean-N: distances and measures of each method). The Windows program reads and
# writes in folders whose names have spaces and non-ASCII characters, and reads OFF, OBJ and
# labels CSV files with CRLF line ends (the Linux run reads the same files with LF ends).
#   same_results_test.sh CANONFORM CANONFORM.EXE PLYCHECK WORKDIR
set -u
lin=$(realpath "$1"); exe=$(realpath "$2"); plycheck=$(realpath "$3"); work=$4
wine=$(realpath "$(dirname "$0")/../../tools/wine.sh")
. "$(dirname "$0")/../e2e/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
echo "canonform.exe under Wine against the Linux build, bit for bit"
win() { "$wine" "$exe" "$@"; }
crlf() { sed 's/$/\r/' "$1" > "$2"; }  # a copy with CRLF line ends

# Inputs, made by the Linux build: two figures (1000 vertices, pose 4; 600 vertices, pose 5, for
# the geodesic forms, which keep all pairs), the first also as CRLF OFF and OBJ; a collection of
# two classes in three poses, its labels with CRLF line ends for the Windows run.
mkdir -p in
"$lin" generate in/A.ply --vertices 1000 --pose 4 > /dev/null &&
"$lin" generate in/S.ply --vertices 600 --pose 5 > /dev/null &&
"$lin" generate in/A_lf.off --vertices 1000 --pose 4 > /dev/null &&
"$lin" generate in/A_lf.obj --vertices 1000 --pose 4 > /dev/null &&
"$lin" generate --collection in/coll --poses 3 --classes standard,stocky --vertices 2000 > /dev/null || { fail "the inputs"; finish; exit; }
crlf in/A_lf.off in/A_crlf.off; crlf in/A_lf.obj in/A_crlf.obj
check "the CRLF copies have CR before every line end" bash -c "grep -c \$'\\r\$' in/A_crlf.off | grep -q \$(wc -l < in/A_lf.off)"
# The Windows run's copy of the inputs: in a folder, and under names, with spaces and non-ASCII
# characters; the collection's labels with CRLF line ends.
wdir="entrée ü 形"
mkdir -p "$wdir"
cp in/A.ply "$wdir/figure à.ply"; cp in/S.ply "$wdir/S ü.ply"; cp in/A_crlf.off "$wdir/A crlf.off"
cp in/A_crlf.obj "$wdir/A crlf.obj"; cp -r in/coll "$wdir/collection é"
crlf in/coll/labels.csv "$wdir/collection é/labels.csv"

methods=$("$lin" canonical --help | grep -oE 'euclidean-[A-Z]|geodesic-[a-z]+' | sort -u)
echo "methods of the registry: $(echo $methods)"
# run_all OUTDIR A S OFF OBJ COLLECTION TOOL...: every compared output into OUTDIR
run_all() {
  local out=$1 A=$2 S=$3 off=$4 obj=$5 coll=$6; shift 6
  local t=(--threads 2 --quiet)
  mkdir -p "$out"
  "$@" conformal "$A" "$out/conformal.ply" > /dev/null || return 1
  "$@" features "$A" "$out/features.ply" > /dev/null 2>&1 || return 1
  for m in $methods; do
    local input=$A; case $m in geodesic-*) input=$S ;; esac
    "$@" canonical "$input" "$out/canonical_$m.ply" --method "$m" "${t[@]}" || return 1
  done
  "$@" canonical "$off" "$out/canonical_off.ply" "${t[@]}" || return 1
  "$@" canonical "$obj" "$out/canonical_obj.ply" "${t[@]}" || return 1
  "$@" codebook "$out/cb.bin" "$A" "$S" --words 40 --training lloyd > /dev/null 2>&1 || return 1
  "$@" descriptor "$A" "$out/A.cfvd" --codebook "$out/cb.bin" > /dev/null || return 1
  "$@" descriptor "$S" "$out/S.cfvd" --codebook "$out/cb.bin" > /dev/null || return 1
  "$@" descriptor "$off" "$out/off.cfvd" --codebook "$out/cb.bin" > /dev/null || return 1
  "$@" distance "$out/distances.bin" "$out/A.cfvd" "$out/S.cfvd" "$out/off.cfvd" --threads 2 > /dev/null || return 1
  "$@" retrieve --dataset "$coll" --out "$out/run" --method none,euclidean-N --words 30 --codebook lloyd \
       --threads 2 > /dev/null 2>&1 || return 1
  "$@" evaluate "$out/run/euclidean-N/distances.bin" --labels "$coll/labels.csv" --json | tr -d '\r' > "$out/evaluate.json"
}
t0=$(date +%s.%N)
check "the Linux build's outputs" run_all linux in/A.ply in/S.ply in/A_lf.off in/A_lf.obj in/coll "$lin"
t1=$(date +%s.%N)
wout="sortie é ü"
check "canonform.exe's outputs under Wine (in '$wout')" \
  run_all "$wout" "$wdir/figure à.ply" "$wdir/S ü.ply" "$wdir/A crlf.off" "$wdir/A crlf.obj" "$wdir/collection é" win
t2=$(date +%s.%N)
echo "  (Linux $(echo "$t1 - $t0" | bc) s, Windows under Wine $(echo "$t2 - $t1" | bc) s)"

# A descriptor file names its mesh's path in its header (CFVD, version, length, name): the rest,
# every number, must be the same bits.
cfvd_body() { /usr/bin/python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(); n=struct.unpack_from('<I', d, 8)[0]; sys.stdout.buffer.write(d[12 + n:])" "$1"; }
same() {  # same NAME: linux/NAME and the Windows run's NAME, bit for bit
  local name=$1
  if [ ! -e "$wout/$name" ]; then fail "$name: not written by canonform.exe"; return; fi
  if cmp -s "linux/$name" "$wout/$name"; then pass "$name: the same bits"; return; fi
  case "$name" in
    *.cfvd) if cmp -s <(cfvd_body "linux/$name") <(cfvd_body "$wout/$name"); then
              pass "$name: the same bits but the mesh path in the header ('$(head -c 200 "$wout/$name" | tail -c +13 | head -c 40 | tr -d '\0')...')"
              return; fi ;;
  esac
  case "$name" in
    *.ply) fail "$name differs: $("$plycheck" "$wout/$name" "linux/$name" | python3 -c 'import json,sys; j=json.load(sys.stdin); print("max coordinate difference", j.get("max_position_diff"), "quality", j.get("max_quality_diff"))')" ;;
    *) fail "$name differs ($(cmp "linux/$name" "$wout/$name" 2>&1 | head -1))" ;;
  esac
}
for f in linux/*.ply linux/*.cfvd linux/*.bin linux/evaluate.json; do same "${f#linux/}"; done
check "the CRLF OFF and OBJ give the canonical form of the PLY (Linux)" cmp -s linux/canonical_off.ply linux/canonical_euclidean-N.ply
check "  ... and under Wine" cmp -s "$wout/canonical_off.ply" linux/canonical_euclidean-N.ply
check "  ... the OBJ under Wine" cmp -s "$wout/canonical_obj.ply" linux/canonical_euclidean-N.ply
for m in none euclidean-N; do
  for f in distances.bin metrics.json pr.csv models.csv codebook.bin; do same "run/$m/$f"; done
done
# The run's list of models: the same names and classes, the paths in the non-ASCII folder.
check "run/collection.csv: the same models and classes, the paths under '$wdir/collection é/'" bash -c "
  diff <(cut -d, -f1,2 linux/run/collection.csv) <(cut -d, -f1,2 '$wout/run/collection.csv') &&
  [ \$(grep -c ',$wdir/collection é/meshes/' '$wout/run/collection.csv') -eq 6 ]"
# The report: the same measures per method (its time columns aside), the collection named.
measures() { grep -E '^\| (none|euclidean-N) \|' "$1" | cut -d'|' -f2-10; }
measures linux/run/report.md > measures_linux.txt; measures "$wout/run/report.md" > measures_windows.txt
check "run/report.md: the same measures for none and euclidean-N" \
  bash -c "[ \$(wc -l < measures_linux.txt) -eq 2 ] && diff measures_linux.txt measures_windows.txt"
check "run/report.md names the non-ASCII collection" grep -q "6 meshes from \`$wdir/collection é\`" "$wout/run/report.md"
check "no temporary file left behind" bash -c "! find '$wout' -name '.*tmp*' | grep -q ."
finish
