#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end tests of the filter_canonical plugin in the real meshlabserver (MeshLab 2020.09,
# under xvfb-run), through a private prefix made by tools/install.sh --prefix (the documented
# install without root). Each shipped script is run; the saved quality values and layers are
# compared with the canonform tool's results on the same file; bad input must fail with the
# reason in meshlabserver's output and leave no output file.
#   meshlabserver_test.sh SOURCE_DIR BUILD_DIR CANONFORM PLYCHECK WORKDIR
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); plycheck=$(realpath "$4"); work=$5
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)

echo "filter_canonical in meshlabserver, end to end"
"$src/tools/install.sh" --prefix "$work/prefix" --build-dir "$build" > install.log 2>&1
check "private install (tools/install.sh --prefix)" test -x "$work/prefix/bin/meshlabserver"
scripts="$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_canonical"
check "scripts shipped in the plugin folder" test -f "$scripts/euclidean_canonical_form.mlx"

mls() {  # meshlabserver with a virtual X server; output in $log
  log=$1; shift
  xvfb-run -a -s "-screen 0 1280x1024x24" "$work/prefix/bin/meshlabserver" "$@" > "$log" 2>&1
}

"$cf" generate fig.ply --vertices 2500 --pose 4

# Conformal factor ------------------------------------------------------------------------------
mls cf.log -i fig.ply -o ml_cf.ply -m vq vc -s "$scripts/conformal_factor.mlx"
check "Conformal factor: meshlabserver succeeds" test $? -eq 0
check "Conformal factor: plugin loaded and logged" grep -q "Conformal factor of 'fig.ply'" cf.log
check "Conformal factor: the log names the version ($("$cf" --version))" grep -q "$("$cf" --version): Conformal factor" cf.log
"$cf" conformal fig.ply ref_cf.ply
"$plycheck" ml_cf.ply ref_cf.ply > cf.json
check "Conformal factor: saved quality equals the tool's (float precision)" \
  json cf.json "j['same_vertex_count'] and j['max_quality_diff'] < 1e-4 and j['quality_min'] == 0 and abs(j['quality_max'] - 1) < 1e-6"

# Feature points, with the point-cloud layer ---------------------------------------------------
sed 's/name="add_layer" type="RichBool" value="false"/name="add_layer" type="RichBool" value="true"/' \
  "$scripts/feature_points.mlx" > fp_layer.mlx
mls fp.log -i fig.ply -o ml_fp_mesh.ply -l 0 -m vq -o ml_fp_points.ply -l 1 -m vq -s fp_layer.mlx
check "Feature points: meshlabserver succeeds" test $? -eq 0
"$cf" features fig.ply ref_fp.ply --json > ref_fp.json
"$plycheck" ml_fp_points.ply ref_fp.ply > fp.json
check "Feature points: layer 1 holds the same points as the tool's" \
  json fp.json "j['faces'] == 0 and j['same_vertex_count'] and j['max_position_diff'] < 1e-5 and j['max_quality_diff'] < 1e-4"
n=$(/usr/bin/python3 -c "import json; print(json.load(open('ref_fp.json'))['feature_points'])")
check "Feature points: the log names the count" grep -q "Feature points of 'fig.ply': $n selected" fp.log

# Euclidean canonical form, in a new layer ------------------------------------------------------
mls ecf.log -i fig.ply -o ml_canon.ply -l 1 -m vq -s "$scripts/euclidean_canonical_form.mlx"
check "Euclidean canonical form: meshlabserver succeeds" test $? -eq 0
check "Euclidean canonical form: SMACOF reported in the log" grep -q "SMACOF iterations" ecf.log
"$cf" canonical fig.ply ref_canon.ply --quiet
"$plycheck" ml_canon.ply ref_canon.ply > ecf.json
"$plycheck" ml_canon.ply fig.ply > ecf_vs_input.json
check "Euclidean canonical form: layer 1 matches the tool's result (float precision)" \
  json ecf.json "j['same_vertex_count'] and j['faces'] > 4000 and j['aligned_rms'] < 1e-3 and j['max_quality_diff'] < 1e-4"
check "Euclidean canonical form: layer 1 is not the input pose" json ecf_vs_input.json "j['aligned_rms'] > 0.01"

# In place (new_layer = false): the current mesh itself changes --------------------------------
sed 's/name="new_layer" type="RichBool" value="true"/name="new_layer" type="RichBool" value="false"/' \
  "$scripts/euclidean_canonical_form.mlx" > ecf_inplace.mlx
mls inplace.log -i fig.ply -o ml_inplace.ply -m vq -s ecf_inplace.mlx
"$plycheck" ml_inplace.ply ref_canon.ply > inplace.json
check "Euclidean canonical form in place: same result" json inplace.json "j['same_vertex_count'] and j['aligned_rms'] < 1e-3"

# Geodesic canonical form (least squares), and its refusal of an over-large mesh ---------------
"$cf" generate fig1k.ply --vertices 800 --pose 4
mls geo.log -i fig1k.ply -o ml_geo.ply -l 1 -m vq -s "$scripts/geodesic_canonical_form.mlx"
check "Geodesic canonical form: meshlabserver succeeds" test $? -eq 0
check "Geodesic canonical form: estimate and timings logged" bash -c "grep -q 'estimated about' geo.log && grep -q 'geodesics .* s, MDS' geo.log"
"$plycheck" ml_geo.ply fig1k.ply > geo.json
check "Geodesic canonical form: layer 1 keeps the mesh and changes the pose" json geo.json "j['same_vertex_count'] and j['aligned_rms'] > 0.01"
sed 's/name="max_memory_gib" type="RichFloat" value="4"/name="max_memory_gib" type="RichFloat" value="0.001"/' \
  "$scripts/geodesic_canonical_form.mlx" > geo_small_limit.mlx
mls geo_refused.log -i fig.ply -o bad_geo.ply -l 1 -m vq -s geo_small_limit.mlx
rc=$?
check "Geodesic canonical form: refuses over the memory limit, naming memory and time ($rc)" \
  bash -c "[ $rc -ne 0 ] && grep -q 'needs about .* GiB and .* s' geo_refused.log"
check "Geodesic canonical form: no output when refused" test ! -e bad_geo.ply

# Depth view descriptor (filter_viewdescriptor) --------------------------------------------------
vscripts="$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_viewdescriptor"
"$cf" codebook cb.bin fig.ply --words 100 2>/dev/null
sed -e "s|name=\"output_file\" type=\"RichString\" value=\"descriptor.cfvd\"|name=\"output_file\" type=\"RichString\" value=\"$work/ml.cfvd\"|" \
    -e "s|name=\"codebook_file\" type=\"RichString\" value=\"\"|name=\"codebook_file\" type=\"RichString\" value=\"$work/cb.bin\"|" \
    -e "s|name=\"views_folder\" type=\"RichString\" value=\"\"|name=\"views_folder\" type=\"RichString\" value=\"$work/ml_views\"|" \
    "$vscripts/depth_view_descriptor.mlx" > dv.mlx
mls dv.log -i fig.ply -s dv.mlx
check "Depth view descriptor: meshlabserver succeeds and logs keypoint counts" bash -c "[ $? -eq 0 ] && grep -q 'SIFT keypoints per view' dv.log"
check "Depth view descriptor: 66 PNG views written" bash -c "[ \$(ls ml_views/view_*.png | wc -l) -eq 66 ]"
"$cf" descriptor fig.ply cli.cfvd --codebook cb.bin
"$cf" distance dv.bin ml.cfvd cli.cfvd > dv_dist.log 2>&1
check "Depth view descriptor: the reader accepts MeshLab's file; distance to the tool's is small" /usr/bin/python3 -c "
import csv; D = [[float(x) for x in r] for r in csv.reader(open('dv.bin.csv'))]; assert D[0][1] < 5, D"
"$cf" features fig.ply cloud_dv.ply
mls dv_bad.log -i cloud_dv.ply -s dv.mlx
check "Depth view descriptor: a point cloud fails with the reason" bash -c "[ $? -ne 0 ] && grep -q 'point cloud' dv_bad.log"

# All three in one script (the README example's pipeline) --------------------------------------
{ echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
  for s in conformal_factor feature_points euclidean_canonical_form; do
    sed -n '/<filter/,/<\/filter>/p' "$scripts/$s.mlx"; done
  echo '</FilterScript>'; } > all.mlx
mls all.log -i fig.ply -o all_canon.ply -l 1 -m vq -s all.mlx
check "three filters in one script" test $? -eq 0

# Other formats: meshlabserver converts, the tool reads OBJ, STL and OFF ---------------------
for ext in obj stl off; do
  mls conv_$ext.log -i fig.ply -o fig.$ext
  "$cf" conformal fig.$ext cf_$ext.ply
  "$plycheck" cf_$ext.ply ref_cf.ply > conv_$ext.json
  if [ "$ext" = stl ]; then  # STL repeats vertices per face: merged on reading, in another order
    check "canonform reads STL (vertices merged: same counts)" json conv_$ext.json "j['same_vertex_count'] and j['faces'] == 4996"
  else                       # MeshLab writes OBJ/OFF coordinates with fewer digits
    check "canonform reads ${ext^^} (same conformal factor to 1e-3)" json conv_$ext.json "j['same_vertex_count'] and j['max_quality_diff'] < 1e-3"
  fi
  check "canonform canonical on ${ext^^}" "$cf" canonical fig.$ext canon_$ext.ply --quiet
done

# An open mesh (boundary) is accepted, with a note in the log ---------------------------------
awk 'BEGIN { n = 12; print "OFF"; print n * n, 2 * (n - 1) * (n - 1), 0
  for (j = 0; j < n; j++) for (i = 0; i < n; i++) print i / n, j / n, 0.2 * sin(i / 2.0) * cos(j / 3.0)
  for (j = 0; j < n - 1; j++) for (i = 0; i < n - 1; i++) { v = j * n + i
    print 3, v, v + 1, v + n + 1; print 3, v, v + n + 1, v + n } }' > open.off
mls open.log -i open.off -o ml_open.ply -m vq -s "$scripts/conformal_factor.mlx"
check "open mesh: accepted with a note on its boundary" bash -c "[ $? -eq 0 ] && grep -q 'note: the mesh is open' open.log"
, the reason in the output, no output file ---------------------------
"$cf" features fig.ply cloud.ply
mls cloud.log -i cloud.ply -o bad_cloud.ply -m vq -s "$scripts/euclidean_canonical_form.mlx"
rc=$?
check "point cloud: non-zero exit ($rc) with the reason" bash -c "[ $rc -ne 0 ] && grep -q 'point cloud' cloud.log"
check "point cloud: no output file" test ! -e bad_cloud.ply
printf 'OFF\n3 1 0\n0 0 0\n1 0\n' > broken.off
mls broken.log -i broken.off -o bad_broken.ply -m vq -s "$scripts/conformal_factor.mlx"
rc=$?
check "broken file: non-zero exit ($rc) with the reason" bash -c "[ $rc -ne 0 ] && grep -q 'Failed loading' broken.log"
check "broken file: no output file" test ! -e bad_broken.ply
{ echo OFF; echo "12 12 0"
  for o in 0 3 6; do echo "$o 0 0"; echo "$((o + 1)) 0 0"; echo "$o 1 0"; echo "$o 0 1"; done
  for b in 0 4 8; do echo "3 $b $((b + 2)) $((b + 1))"; echo "3 $b $((b + 1)) $((b + 3))"
                     echo "3 $b $((b + 3)) $((b + 2))"; echo "3 $((b + 1)) $((b + 2)) $((b + 3))"; done; } > comps.off
mls comps.log -i comps.off -o bad_comps.ply -m vq -s "$scripts/feature_points.mlx"
rc=$?
check "several components: non-zero exit ($rc) with the reason" bash -c "[ $rc -ne 0 ] && grep -q 'connected components' comps.log"
# A bad parameter value is named (the registry checks filter parameters as the tool's options) --
sed 's/name="beta" type="RichFloat" value="0"/name="beta" type="RichFloat" value="-1"/' \
  "$scripts/euclidean_canonical_form.mlx" > ecf_bad_beta.mlx
mls bad_beta.log -i fig.ply -o bad_beta.ply -l 1 -s ecf_bad_beta.mlx
rc=$?
check "beta = -1: non-zero exit ($rc) naming the parameter and value" \
  bash -c "[ $rc -ne 0 ] && grep -q \"beta must be a positive number (or 0 for the default), got '-1'\" bad_beta.log && [ ! -e bad_beta.ply ]"
# Repair (issue 11): a mesh with 5 zero-area faces is refused by default, let through with repair ----
# (the construction of tests/e2e/bad_input_test.sh: coordinates on a 2^-10 grid, exact midpoints)
"$cf" generate fig1200.off --vertices 1200 --pose 1
awk 'function q(x) { return (x >= 0 ? int(x * 1024 + 0.5) : -int(-x * 1024 + 0.5)) / 1024 }
  NR == 2 { n = $1; f = $2; next } NR <= n + 2 { v[NR - 3] = sprintf("%.17g %.17g %.17g", q($1), q($2), q($3)); next }
  { face[NR - n - 3] = $0 }
  END { nv = n; nf = f
        for (s = 0; s < 5; s++) { k = int(s * f / 5) + 1; split(face[k], t, " "); a = t[2]; b = t[3]; c = t[4]
          split(v[a], pa, " "); split(v[b], pb, " ")
          v[nv] = sprintf("%.17g %.17g %.17g", (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2, (pa[3] + pb[3]) / 2)
          face[k] = "3 " a " " nv " " c; face[nf++] = "3 " nv " " b " " c; face[nf++] = "3 " b " " a " " nv; nv++ }
        print "OFF"; print nv, nf, 0; for (i = 0; i < nv; i++) print v[i]; for (i = 0; i < nf; i++) print face[i] }' \
  fig1200.off > slivers.off
cp slivers.off ml_slivers.off
mls slivers.log -i ml_slivers.off -o bad_slivers.ply -l 1 -s "$scripts/euclidean_canonical_form.mlx"
rc=$?
check "5 zero-area faces: refused by default ($rc), naming them" \
  bash -c "[ $rc -ne 0 ] && grep -q '5 degenerate faces' slivers.log && [ ! -e bad_slivers.ply ]"
sed 's/name="repair" type="RichBool" value="false"/name="repair" type="RichBool" value="true"/' \
  "$scripts/euclidean_canonical_form.mlx" > ecf_repair.mlx
mls repair.log -i ml_slivers.off -o ml_repaired.ply -l 0 -o ml_repaired_form.ply -l 1 -s ecf_repair.mlx
check "repair = true: succeeds and logs what it removed" \
  bash -c "[ $? -eq 0 ] && grep -q 'repair: 5 zero-area or repeated-vertex faces removed' repair.log"
"$cf" canonical ml_slivers.off ref_repaired.ply --repair --quiet 2> /dev/null
"$plycheck" ml_repaired_form.ply ref_repaired.ply > repair.json
check "repair = true: the document's mesh is repaired and the form equals the tool's --repair (float precision)" \
  json repair.json "j['same_vertex_count'] and j['aligned_rms'] < 1e-3"
# MeshLab 2020.09's own OFF loader on an out-of-range face index (docs/bad-input.md) --
{ echo OFF; echo "12 12 0"; for k in 0 1 2 3 4 5 6 7 8 9 10 11; do echo "$k $((k * k % 7)) $((k % 4))"; done
  echo "3 0 100000000 10"; for k in 1 2 3 4 5 6 7 8 9 10 11; do echo "3 $k $(((k + 1) % 12)) $(((k + 2) % 12))"; done; } > index.off
mls index.log -i index.off -o bad_index.ply
rc=$?
check "MeshLab 2020.09's OFF loader crashes on face index 100000000 before any filter (exit $rc, as docs/bad-input.md says)" \
  bash -c "[ $rc -eq 139 ] || grep -q 'Segmentation fault' index.log"
"$cf" conformal index.off bad_index.ply > index_cf.log 2>&1
check "the canonform tool names the line instead" grep -q "face index 100000000 on line 15 is out of range" index_cf.log
"$cf" check index.off --repair index_fixed.ply > index_check.log 2>&1
check "canonform check names it with MeshLab's crash, and --repair writes a copy without that face" \
  bash -c "grep -q 'dropped 1 faces' index_check.log && '$cf' check index.off | grep -q 'MeshLab crashes on this file'"
mls index_fixed.log -i index_fixed.ply -o ml_index_fixed.ply
rc=$?
check "meshlabserver opens the repaired copy (exit $rc)" bash -c "[ $rc -eq 0 ] && [ -s ml_index_fixed.ply ] && grep -q '11 fn' index_fixed.log"
finish
