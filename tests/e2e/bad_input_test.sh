#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Hostile and broken input through every command of the canonform tool (issue 11): each answers
# exit 1 (2 for usage) with a message naming the real cause, writes no output and leaves no
# temporary file; --repair lets a mesh with 5 zero-area faces through with one log line; every
# numeric option of every command refuses NaN, -1 and 1e300; retrieve lists a missing mesh as a
# failure, recomputes a corrupt cache entry, checks the labels before any work and still writes
# the distances when the classes are too small for the measures.
#   bad_input_test.sh CANONFORM WORKDIR
# CANONFORM_PICTURES=0: the tool was built without Qt (the Windows build, tests/windows/): its
# picture command is expected to refuse every input, saying so.
set -u
cf=$(realpath "$1"); work=$2
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
echo "canonform tool: bad input, end to end"

# expect RC PATTERN DESCRIPTION -- COMMAND...: exit RC, stderr/stdout matching PATTERN, no file
# named out* or .out* left behind.
expect() {
  local want=$1 pattern=$2 what=$3; shift 4
  rm -rf out* .out*
  "$@" > err.txt 2>&1
  local rc=$?
  if [ $rc -eq "$want" ] && grep -qi -- "$pattern" err.txt && ! ls out* .out* > /dev/null 2>&1; then
    pass "$what -> exit $rc: $(grep -i -m1 -- "$pattern" err.txt | cut -c1-150)"
  else
    fail "$what (exit $rc, want $want and '$pattern'; files: $(ls out* .out* 2>/dev/null | tr '\n' ' '); output: $(head -c 400 err.txt))"
  fi
}

"$cf" generate fig.off --vertices 1200 --pose 1 || exit 1
{ echo OFF; echo "12 12 0"; for k in 0 1 2 3 4 5 6 7 8 9 10 11; do echo "$k $((k * k % 7)) $((k % 4))"; done
  echo "FACE"; for k in 1 2 3 4 5 6 7 8 9 10 11; do echo "3 $k $(((k + 1) % 12)) $(((k + 2) % 12))"; done; } > template.off
sed 's/^FACE$/3 0 100000000 10/' template.off > index_huge.off
sed 's/^FACE$/3 0 12 10/' template.off > index_n.off
sed 's/^FACE$/3 0 -1 10/' template.off > index_negative.off
sed -e 's/^12 12 0$/40000000 12 0/' -e 's/^FACE$/3 0 1 2/' template.off > lies.off
sed -e 's/^12 12 0$/2000000000 12 0/' -e 's/^FACE$/3 0 1 2/' template.off > lies2e9.off
printf 'OFF\n0 0 0\n' > empty_mesh.off
mkdir -p folder.off folder.cfvd folder.bin folder.csv
# Coordinates of 1e200 and 1e-200: the figure scaled.
awk 'NR <= 2 { print; if (NR == 2) n = $1; next } NR <= n + 2 { printf "%.17g %.17g %.17g\n", $1 * 1e200, $2 * 1e200, $3 * 1e200; next } { print }' fig.off > big.off
awk 'NR <= 2 { print; if (NR == 2) n = $1; next } NR <= n + 2 { printf "%.17g %.17g %.17g\n", $1 * 1e-200, $2 * 1e-200, $3 * 1e-200; next } { print }' fig.off > small.off
# NaN, a point cloud, all vertices at one point (for picture).
awk 'NR == 3 { print "nan 0 0"; next } { print }' fig.off > nan.off
awk 'NR <= 2 { print; if (NR == 2) n = $1; next } NR <= n + 2 { print "1 1 1"; next } { print }' fig.off > onepoint.off
"$cf" features fig.off cloud.ply > /dev/null 2>&1
# 5 zero-area faces: 5 faces (a, b, c) split at the midpoint M of (a, b) into (a, M, c), (M, b, c)
# plus the sliver (b, a, M) - the T-junction filler CAD exports leave (a closed, manifold mesh).
# Coordinates on a 2^-10 grid, so that M is exactly collinear in float (MeshLab) as in double.
awk 'function q(x) { return (x >= 0 ? int(x * 1024 + 0.5) : -int(-x * 1024 + 0.5)) / 1024 }
  NR == 2 { n = $1; f = $2; next } NR <= n + 2 { v[NR - 3] = sprintf("%.17g %.17g %.17g", q($1), q($2), q($3)); next }
  { face[NR - n - 3] = $0 }
  END { nv = n; nf = f; out = 0
        for (s = 0; s < 5; s++) { k = int(s * f / 5) + 1; split(face[k], t, " "); a = t[2]; b = t[3]; c = t[4]
          split(v[a], pa, " "); split(v[b], pb, " ")
          v[nv] = sprintf("%.17g %.17g %.17g", (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2, (pa[3] + pb[3]) / 2)
          face[k] = "3 " a " " nv " " c; face[nf++] = "3 " nv " " b " " c; face[nf++] = "3 " b " " a " " nv; nv++ }
        print "OFF"; print nv, nf, 0; for (i = 0; i < nv; i++) print v[i]; for (i = 0; i < nf; i++) print face[i] }' \
  fig.off > slivers.off

# --- the issue's reproductions, through every command that reads a mesh ---------------------------
mesh_commands="conformal features canonical simplify descriptor views"
[ "${CANONFORM_PICTURES:-1}" = 0 ] && mesh_commands="conformal features canonical simplify descriptor"  # views refuses first
for cmd in $mesh_commands; do
  extra=""; [ $cmd = simplify ] && extra="--vertices 500"
  out=out.ply; [ $cmd = descriptor ] && out=out.cfvd; [ $cmd = views ] && out=out_views
  expect 1 "face index 100000000 on line 15 is out of range: the file has 12 vertices" "$cmd: face index 100000000 (was a segfault)" -- "$cf" $cmd index_huge.off $out $extra
  expect 1 "face index 12 on line 15 is out of range" "$cmd: face index = #V (was an out-of-bounds read)" -- "$cf" $cmd index_n.off $out $extra
  expect 1 "the header claims 40000000 vertices.*the header lies" "$cmd: a header claiming 40 million vertices (was 2.5 GB)" -- "$cf" $cmd lies.off $out $extra
done
expect 1 "face index -1 on line 15 is out of range" "canonical: face index -1" -- "$cf" canonical index_negative.off out.ply
expect 1 "claims 2000000000 vertices.*the header lies" "canonical: 2e9 vertices (was std::bad_alloc)" -- "$cf" canonical lies2e9.off out.ply
expect 1 "is a folder" "canonical: a folder as the input mesh" -- "$cf" canonical folder.off out.ply
"$cf" simplify fig.off fig600.off --vertices 600 > /dev/null  # (a tenth of a figure's cost under the sanitizers)
if [ "${CANONFORM_PICTURES:-1}" = 0 ]; then
  for m in empty_mesh.off cloud.ply nan.off onepoint.off fig.off; do
    expect 1 "built without Qt" "picture: $m refused by a build without Qt, saying so" -- "$cf" picture out.png $m
  done
else
expect 1 "the mesh is empty" "picture: an OFF with 0 vertices (was a segfault)" -- "$cf" picture out.png empty_mesh.off
expect 1 "point cloud" "picture: a point cloud (was a blank image)" -- "$cf" picture out.png cloud.ply
expect 1 "NaN or infinite" "picture: NaN coordinates (was a blank image)" -- "$cf" picture out.png nan.off
expect 1 "are at one point" "picture: all vertices identical (was a blank image)" -- "$cf" picture out.png onepoint.off
expect 1 "a canonical form keeps the vertices of its mesh" "picture: a canonical form of another mesh" -- "$cf" picture out.png fig.off --canonical fig600.off
fi
check "canonical: coordinates of 1e200 are not degenerate faces (were '... degenerate faces')" "$cf" canonical big.off big.ply --quiet
check "canonical: coordinates of 1e-200 are not degenerate faces" "$cf" canonical small.off small.ply --quiet
"$cf" canonical fig.off ref.ply --json > ref.json
"$cf" canonical big.off big.ply --json > big.json
"$cf" canonical small.off small.ply --json > small.json
check "canonical: the 1e200 and 1e-200 figures give the figure's form (same feature points, iterations, stress)" /usr/bin/python3 -c "
import json; r, b, s = (json.load(open(f + '.json')) for f in ('ref', 'big', 'small'))
for x in (b, s):
    assert x['feature_points'] == r['feature_points'] and abs(x['iterations'] - r['iterations']) <= 2, (r, x)
    assert abs(x['final_stress'] - r['final_stress']) <= 1e-6 * r['final_stress'], (r, x)"

# --- outputs: the format the name says, or refused; dotted folders ------------------------------
for ext in off obj stl; do
  "$cf" canonical fig.off form.$ext --quiet
  check "an output named .$ext is $ext (was binary PLY)" bash -c "[ \"\$(head -c 3 form.$ext)\" = '$(case $ext in off) echo OFF;; obj) echo '# c';; stl) echo can;; esac)' ] && '$cf' conformal form.$ext cf_$ext.ply"
done
expect 2 "unsupported mesh format '.xyz'" "an output named .xyz is a usage error before any work" -- "$cf" canonical fig.off out.xyz
expect 2 "cannot hold a point cloud" "features to .stl is a usage error before any work" -- "$cf" features fig.off out.stl
mkdir -p v1.2
"$cf" descriptor fig.off fig.cfvd > /dev/null 2>&1
"$cf" codebook cb.bin fig.off --words 20 > /dev/null 2>&1
expect 1 "1000000 words asked for, but there are only" "codebook: more words than descriptors is refused, naming --words (was a silent codebook of every descriptor)" -- \
  "$cf" codebook cb_big.bin fig.off --words 1000000
check "  ... and no codebook file is written" test ! -e cb_big.bin
for m in a b c; do "$cf" descriptor fig.off $m.cfvd --codebook cb.bin > /dev/null 2>&1; done
check "an output without extension in a dotted folder (distance v1.2/D, was 'cannot write')" \
  bash -c "'$cf' distance v1.2/D a.cfvd b.cfvd c.cfvd 2>/dev/null && [ \$(stat -c %s v1.2/D) -eq 36 ] && '$cf' generate v1.2/G --vertices 500 && [ \"\$(head -c 3 v1.2/G)\" = ply ]"

# --- folders and broken files as descriptor, codebook, matrix, labels ---------------------------
expect 1 "folder.cfvd': it is a folder" "distance: a folder as a descriptor (was 'truncated, 0 bytes')" -- "$cf" distance out.bin folder.cfvd a.cfvd
expect 1 "it is a folder" "descriptor: a folder as the codebook" -- "$cf" descriptor fig.off out.cfvd --codebook folder.bin
printf 'path,class\na,x\nb,x\nc,y\n' > labels3.csv
expect 1 "it is a folder" "evaluate: a folder as the matrix" -- "$cf" evaluate folder.bin --labels labels3.csv
expect 1 "it is a folder" "evaluate: a folder as the labels" -- "$cf" evaluate v1.2/D --labels folder.csv
printf 'not a matrix' > bad.bin
expect 1 "not a square float32 matrix" "evaluate: a broken matrix" -- "$cf" evaluate bad.bin --labels labels3.csv
printf 'path,class\na,x\nb,\nc,y\n' > labels_noclass.csv
expect 1 "row 3 has no class" "evaluate: a labels row without a class" -- "$cf" evaluate v1.2/D --labels labels_noclass.csv
printf 'path,class\na,cl"ass\nb,cl"ass\nc,cl"ass\nd,\xff\xfe\ne,\xff\xfe\nf,\xff\xfe\n' > labels_quote.csv
printf '0,1,1,2,2,2\n1,0,1,2,2,2\n1,1,0,2,2,2\n2,2,2,0,1,1\n2,2,2,1,0,1\n2,2,2,1,1,0\n' > six.csv
"$cf" evaluate six.csv --labels labels_quote.csv --json > eval.json 2> eval.err
cat > eval_check.py <<'PY'
import json
j = json.load(open('eval.json'))
assert 'cl"ass' in j['classes'] and '\ufffd\ufffd' in j['classes'] and j['micro']['nn'] == 1, j
PY
check "evaluate --json: class names with \" and invalid UTF-8 give valid JSON (was invalid)" /usr/bin/python3 eval_check.py

# --- options: NaN, -1 and 1e300 for every numeric option of every command -----------------------
expect 2 "beta must be a positive number.*'nan'" "canonical --beta nan (was replaced by 130)" -- "$cf" canonical fig.off out.ply --beta nan
expect 2 "beta must be a positive number.*'-1'" "canonical --beta -1 (was replaced by 130)" -- "$cf" canonical fig.off out.ply --beta -1
expect 2 "max_memory_gib must be a finite number.*'nan'" "canonical --max-memory-gib nan (switched the guard off)" -- "$cf" canonical fig.off out.ply --method geodesic-ls --max-memory-gib nan
options_checked=0
declare -A positional=([conformal]="fig.off out.ply" [features]="fig.off out.ply" [canonical]="fig.off out.ply"
  [simplify]="fig.off out.ply" [generate]="out.ply" [picture]="out.png fig.off" [views]="fig.off out_views"
  [codebook]="out.bin fig.off" [descriptor]="fig.off out.cfvd" [distance]="out.bin a.cfvd b.cfvd"
  [retrieve]="--dataset coll --out out_run" [evaluate]="six.csv --labels labels3.csv" [grid]="out.png run"
  [slurm]="--dataset coll --out out_slurm" [index]="run" [query]="run fig.off")
for cmd in conformal features canonical simplify generate picture views codebook descriptor distance retrieve evaluate grid \
           slurm index query; do
  # Options with a numeric type in the command's --help (CLI11 prints INT, UINT or FLOAT).
  help=$("$cf" $cmd --help 2>/dev/null)
  for opt in $(grep -oE '^ +(-[a-z], ?)?--[a-z-]+(, ?--[a-z-]+)? (INT|UINT|FLOAT)' <<< "$help" | grep -oE -- '--[a-z-]+' | sort -u); do
    # A method parameter is checked by the method that takes it: use the first method its help names.
    method=$(grep -A3 -- "$opt" <<< "$help" | grep -oE 'default: [a-z-]+ ' | head -1 | cut -d' ' -f2)
    margs=""; [ -n "$method" ] && margs="--method $method"
    for value in nan -1 1e300; do
      "$cf" $cmd ${positional[$cmd]} $margs $opt $value > err.txt 2>&1
      rc=$?
      if [ $rc -eq 2 ] && grep -q -- "$value" err.txt; then options_checked=$((options_checked + 1))
      else fail "$cmd $opt $value: exit $rc, want 2 naming the value ($(head -c 200 err.txt))"; fi
    done
  done
done
check "every numeric option of every command refuses nan, -1 and 1e300 ($options_checked cases)" test $options_checked -ge 60

# --- --repair: the 5-zero-area-face mesh --------------------------------------------------------
expect 1 "5 degenerate faces.*--repair" "without --repair: refused, naming the faces and the way through" -- "$cf" canonical slivers.off out.ply
"$cf" canonical slivers.off rep.ply --repair --quiet > rep.out 2> rep.err
check "canonical --repair: succeeds, one log line of what was removed" \
  bash -c "[ $? -eq 0 ] && [ \$(grep -c 'repair:' rep.err) -eq 1 ] && grep -q 'repair: 5 zero-area or repeated-vertex faces removed: ' rep.err"
cat rep.err | sed 's/^/    /'
for cmd in conformal features descriptor; do
  out=r_$cmd.ply; [ $cmd = descriptor ] && out=r.cfvd
  check "$cmd --repair lets the mesh through" "$cf" $cmd slivers.off $out --repair
done

# --- check: every problem named, also those MeshLab's importers crash on; --repair ---------------
cp fig600.off chk.off
n=$(sed -n 2p chk.off | cut -d' ' -f1)  # vertices
check "check: a good mesh -> exit 0, 'ok'" bash -c "'$cf' check chk.off | grep -q 'ok: the filters and the tool accept'"
# face 0 names vertex 100000000 (MeshLab's OFF importer crashes), a duplicated face (non-manifold edges)
awk -v n="$n" 'NR==2 { print $1, $2 + 1, 0; next } NR==3+n { print "3 0 1 100000000"; next } NR==4+n { dup=$0 } { print } END { print dup }' chk.off > chk_bad.off
"$cf" check chk_bad.off > chk1.out 2>&1
rc=$?
check "check: exit 1 and every problem named (index out of range with MeshLab's crash, non-manifold edges)" \
  bash -c "[ $rc -eq 1 ] && grep -q 'face names a vertex the file does not have (first: face index 100000000' chk1.out &&
           grep -q 'MeshLab crashes on this file' chk1.out && grep -q 'non-manifold edges' chk1.out && grep -q '(2 problems)' chk1.out"
"$cf" check chk_bad.off --repair chk_fixed.ply > chk2.out 2>&1
check "check --repair: drops the face, removes the duplicate, exit 0" \
  bash -c "[ $? -eq 0 ] && grep -q 'dropped 1 faces' chk2.out && grep -q '1 duplicate face removed' chk2.out"
check "check --repair: the repaired file passes check and the canonical form runs on it" \
  bash -c "'$cf' check chk_fixed.ply > /dev/null && '$cf' canonical chk_fixed.ply chk_form.ply --quiet"
"$cf" check chk_bad.off --json > chk.json
check "check --json: problems and notes as JSON" json chk.json "len(j['problems']) == 2 and j['readable'] and j['vertices'] == $n"
printf 'OFF\n1000000000000 1 0\n0 0 0\n' > chk_lies.off
"$cf" check chk_lies.off --repair out_lies.ply > chk3.out 2>&1
check "check: a header claiming 10^12 vertices -> unreadable, MeshLab's abort named, nothing written" \
  bash -c "[ $? -eq 1 ] && grep -q 'header lies' chk3.out && grep -q 'MeshLab aborts' chk3.out && [ ! -e out_lies.ply ]"
printf 'OFF\n4 1 0\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n3 0 1 2\n' > chk_nan.off
"$cf" check chk_nan.off --repair chk_nan.ply > chk4.out 2>&1
check "check --repair: NaN coordinates are named as still a problem (not invented), exit 1" \
  bash -c "[ $? -eq 1 ] && grep -q 'still a problem .*NaN' chk4.out"

# --- retrieve ----------------------------------------------------------------------------------
mkdir -p coll
# The six figures from one collection run (under the sanitizers about the cost of one figure alone).
"$cf" generate --collection gen --poses 3 --classes standard,stocky --vertices 600 > /dev/null
for p in 0 1 2; do mv gen/meshes/standard_$p.ply coll/a$p.ply; mv gen/meshes/stocky_$p.ply coll/b$p.ply; done
cp slivers.off coll/s.off
printf 'path,class\na0.ply,a\na1.ply,a\na2.ply,a\nb0.ply,b\nb1.ply,b\nb2.ply,b\nmissing.ply,b\ns.off,a\n' > coll/labels.csv
"$cf" retrieve --dataset coll --out run --method none --words 30 > r1.out 2> r1.err
check "retrieve: a labels row naming a missing file is a listed failure, not a stop" \
  bash -c "[ $? -eq 0 ] && grep -q 'missing: cannot read .*no such file' run/none/failures.txt && grep -q '| none | .* | 6 | 2 |' run/report.md"
check "retrieve: the 5-zero-area-face mesh fails without --repair, naming the faces" grep -q 's: .*5 degenerate faces' run/none/failures.txt
"$cf" retrieve --dataset coll --out run --method none --words 30 --repair > r2.out 2> r2.err
check "retrieve --repair: the mesh goes through, its repair logged" \
  bash -c "grep -q '\[none\] s: repair: 5 zero-area' r2.err && grep -q '| none | .* | 7 | 1 |' run/report.md"
key=$(ls -t run/cache/*.cfvd | head -1)  # an entry of the --repair run
printf 'garbage' > "$key"
"$cf" retrieve --dataset coll --out run --method none --words 30 --repair > r3.out 2> r3.err
check "retrieve: a corrupt cache entry is recomputed (was failing on every re-run)" \
  bash -c "grep -q 'corrupt cache entry recomputed' r3.err && grep -q '(6 from the cache, 1 failed)' r3.err && grep -q '| none | .* | 7 | 1 |' run/report.md"
printf 'path,class\na0.ply,a\na1.ply,\n' > coll/labels_bad.csv
expect 1 "row 3 has no class" "retrieve: the labels are checked before any work" -- "$cf" retrieve --dataset coll --labels coll/labels_bad.csv --out out_run --method none
printf 'path,class\na0.ply,a\na1.ply,a\nb0.ply,b\nb1.ply,b\n' > coll/labels_pairs.csv
"$cf" retrieve --dataset coll --labels coll/labels_pairs.csv --out run2 --method none --words 30 > r4.out 2> r4.err
check "retrieve: classes of two models: said before any work, distances written, no measures and why (was exit 1 at the end)" \
  bash -c "[ $? -eq 0 ] && head -1 r4.err | grep -q 'no class of .* has more than two models' && [ \$(stat -c %s run2/none/distances.bin) -eq 64 ] && grep -q 'No measures for none: no class has more than two models' run2/report.md"
printf 'path,class\na0.ply,a\nsub/a0.ply,b\nb1.ply,b\n' > coll/labels_dup.csv
expect 1 "two models are named 'a0'" "retrieve: two models of one name (their outputs would collide)" -- "$cf" retrieve --dataset coll --labels coll/labels_dup.csv --out out_run --method none
finish
