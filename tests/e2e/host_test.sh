#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end tests in a real host: Debian trixie's MeshLab 2022.02 or forky's MeshLab 2025.07, in
# the root filesystem of tools/host.sh, where the plugins were built with that system's compiler
# and libraries and installed with apt from their Debian package (host.SUITE.prepare). Every
# filter of both plugins is applied by canonform-meshlab (the installed MeshLab's own library,
# plugin manager and IO plugins) on a generated figure; bad input and bad parameters fail with the
# reason and write nothing; the plugin compiled for double precision is refused by the real
# MeshLab with its message; a real articulated mesh (TOSCA, if $CANONFORM_DATA/tosca_r5k is there)
# keeps its vertex count.
#   host_test.sh SOURCE_DIR SUITE CANONFORM PLYCHECK WORKDIR
set -u
src=$(realpath "$1"); suite=$2; cf=$(realpath "$3"); plycheck=$(realpath "$4"); work=$5
. "$(dirname "$0")/lib.sh"
export -f json json_get  # used in bash -c below
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)
case "$suite" in
  trixie) ml=2022.02 ;;
  forky) ml=2025.07 ;;
  *) echo "unknown suite $suite"; exit 2 ;;
esac
series=${ml%%.*}
inside() { CANONFORM_HOST_PREPARE=0 "$src/tools/host.sh" "$suite" "$@"; }
# run NAME ARGS...: canonform-meshlab ARGS inside; NAME.json (stdout), NAME.log (stderr), $rc
run() { local name=$1; shift; inside canonform-meshlab "$@" > "$name.json" 2> "$name.log"; rc=$?; }

echo "canonform-meshlab and the plugins in Debian $suite's MeshLab $ml"

# The package, installed by apt inside (tools/host.sh ran the README's commands) --------------------
inside dpkg-query -W -f='${Status} ${Version}\n' "canonform-plugins-meshlab$series" > pkg.txt 2>&1
check "package canonform-plugins-meshlab$series installed by apt ($(cat pkg.txt))" grep -q "install ok installed" pkg.txt
inside dpkg -L "canonform-plugins-meshlab$series" > files.txt 2>&1
check "the package puts both plugins in MeshLab's plugin folder and canonform-meshlab in /usr/bin" \
  bash -c "grep -qx /usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_canonical.so files.txt &&
           grep -qx /usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_viewdescriptor.so files.txt &&
           grep -qx /usr/bin/canonform-meshlab files.txt"
inside bash -c 'command -v canonform-meshlab; xvfb-run -a meshlab --version' > version.txt 2>&1
check "canonform-meshlab on the PATH; the GUI says MeshLab $ml ($(grep -o 'MeshLab [0-9.]*' version.txt | head -n 1))" \
  bash -c "grep -qx /usr/bin/canonform-meshlab version.txt && grep -q 'MeshLab $ml' version.txt"
inside canonform-meshlab --list > list.txt 2> list.log
for f in compute_conformal_factor compute_feature_points generate_euclidean_canonical_form \
         generate_geodesic_canonical_form compute_depth_view_descriptor; do
  check "MeshLab's function set has $f" grep -q "^$f " list.txt
done
check "MeshLab's own filters are there too ($(wc -l < list.txt) filters)" grep -q "^meshing_decimation_quadric_edge_collapse " list.txt

# Every filter on a generated figure ------------------------------------------------------------------
"$cf" generate fig.ply --vertices 2500 --pose 4 > /dev/null
"$cf" codebook cb.bin fig.ply --words 100 > /dev/null 2>&1
n=$(json_get <("$plycheck" fig.ply) vertices)
sqrt_n=$(/usr/bin/python3 -c "import math; print(math.ceil(math.sqrt($n)))")

run cf fig.ply cf.ply --filter compute_conformal_factor
"$plycheck" cf.ply > cf_ply.json
check "compute_conformal_factor: exit 0, dict {vertices: $n, min < max, residual < 1e-6}" \
  bash -c "[ $rc -eq 0 ] && json cf.json \"j['vertices'] == $n and j['min'] < j['max'] and j['residual'] < 1e-6\""
check "compute_conformal_factor: OUT has the quality in [0, 1] (normalize defaults to true)" \
  json cf_ply.json "j['vertices'] == $n and j['has_quality'] and j['quality_min'] == 0 and abs(j['quality_max'] - 1) < 1e-6"
run cf_raw fig.ply cf_raw.ply --filter compute_conformal_factor --param normalize=false --param colorize=true
"$plycheck" cf_raw.ply > cf_raw_ply.json
check "compute_conformal_factor(normalize=false): OUT's quality spans the dict's raw range" \
  /usr/bin/python3 -c "
import json; d = json.load(open('cf_raw.json')); p = json.load(open('cf_raw_ply.json'))
assert $rc == 0 and abs(p['quality_min'] - d['min']) < 1e-5 and abs(p['quality_max'] - d['max']) < 1e-5, (d, p)"

run fp fig.ply fp.ply --filter compute_feature_points --param fill=random --param seed=3 --param add_layer=true
"$plycheck" fp.ply > fp_ply.json
check "compute_feature_points(fill=random, add_layer=true): $sqrt_n selected, OUT is the point layer" \
  bash -c "[ $rc -eq 0 ] && json fp.json \"j['selected'] == $sqrt_n\" && json fp_ply.json \"j['vertices'] == $sqrt_n and j['faces'] == 0\""
run fp0 fig.ply fp0.ply --filter compute_feature_points --param fill=0
check "compute_feature_points(fill=0, enum by index): the maxima only, OUT is the mesh" \
  bash -c "[ $rc -eq 0 ] && json fp0.json \"j['random'] == 0 and j['selected'] == j['maxima']\" &&
           json <('$plycheck' fp0.ply) \"j['vertices'] == $n\""

run ecf fig.ply canon.ply --filter generate_euclidean_canonical_form --json ecf_file.json
"$plycheck" canon.ply fig.ply > canon_ply.json
echo "    generate_euclidean_canonical_form: $(cat ecf.json)"
check "generate_euclidean_canonical_form: exit 0, converged, stress down, beta 130 (variant N)" \
  bash -c "[ $rc -eq 0 ] && json ecf.json \"j['converged'] and 0 < j['final_stress'] < j['initial_stress'] and j['beta'] == 130 and j['iterations'] > 0\""
check "generate_euclidean_canonical_form: OUT is the new layer, same vertex count, not the input pose (aligned RMS $(json_get canon_ply.json aligned_rms))" \
  json canon_ply.json "j['same_vertex_count'] and j['aligned_rms'] > 0.01"
check "--json FILE holds the same values as stdout" cmp -s ecf.json ecf_file.json
run ecf_a fig.ply canon_a.ply --filter generate_euclidean_canonical_form --param variant=A --param seed=5
check "generate_euclidean_canonical_form(variant=A): ceil(sqrt(N)) = $sqrt_n feature points, beta 10" \
  bash -c "[ $rc -eq 0 ] && json ecf_a.json \"j['feature_points'] == $sqrt_n and j['beta'] == 10\""

run geo fig.ply geo.ply --filter generate_geodesic_canonical_form --param method=classical
check "generate_geodesic_canonical_form(method=classical): exit 0, timings and edge change, OUT $n vertices" \
  bash -c "[ $rc -eq 0 ] && json geo.json \"j['mds_seconds'] >= 0 and 0 < j['mean_relative_edge_change'] < 1\" &&
           json <('$plycheck' geo.ply) \"j['vertices'] == $n\""

run dv fig.ply dv.ply --filter compute_depth_view_descriptor --param "output_file=$work/dv.cfvd" \
    --param "codebook_file=$work/cb.bin" --param seed=0
check "compute_depth_view_descriptor: 66 views, 66 x 100 histogram values summing to the keypoints, file written" \
  bash -c "[ $rc -eq 0 ] && test -s dv.cfvd && json dv.json \"j['views'] == 66 and len(j['keypoints_per_view']) == 66 and len(j['descriptor']) == 66 * 100 and sum(j['descriptor']) == j['keypoints']\""

run dec fig.ply dec.ply --filter meshing_decimation_quadric_edge_collapse --param targetfacenum=2000
check "MeshLab's own filter too (meshing_decimation_quadric_edge_collapse, targetfacenum=2000): OUT has 2000 faces" \
  bash -c "[ $rc -eq 0 ] && json <('$plycheck' dec.ply) \"j['faces'] == 2000\""

# Bad input, bad parameters: exit 1, the reason, no OUT ------------------------------------------------
/usr/bin/python3 -c "
import random; random.seed(1)
print('OFF'); print(100, 0, 0)
for _ in range(100): print(*(round(random.uniform(-1, 1), 6) for _ in range(3)))" > cloud.off
run cloud cloud.off cloud_out.ply --filter generate_euclidean_canonical_form
echo "    point cloud -> exit $rc: $(head -c 300 cloud.log)"
check "a point cloud: exit 1, the reason (a point cloud), no OUT" \
  bash -c "[ $rc -eq 1 ] && grep -q 'point cloud' cloud.log && grep -q 'Failed to apply filter: generate_euclidean_canonical_form' cloud.log && [ ! -e cloud_out.ply ]"
run refuse fig.ply refused.ply --filter generate_geodesic_canonical_form --param max_memory_gib=0.001
check "generate_geodesic_canonical_form(max_memory_gib=0.001): exit 1 naming memory and time, no OUT" \
  bash -c "[ $rc -eq 1 ] && grep -q 'needs about' refuse.log && [ ! -e refused.ply ]"
run enum fig.ply x.ply --filter generate_euclidean_canonical_form --param variant=Z
check "variant=Z: exit 1, MeshLab's enum message ($(grep -o "Enum 'Z'.*" enum.log | head -c 80))" \
  bash -c "[ $rc -eq 1 ] && grep -q \"Enum 'Z' not found. Possible values are 'A'; 'N';\" enum.log"
run key fig.ply x.ply --filter compute_conformal_factor --param normalise=true
check "an unknown keyword: exit 1, 'Parameter normalise not found'" bash -c "[ $rc -eq 1 ] && grep -q 'Parameter normalise not found' key.log"
run value fig.ply x.ply --filter generate_euclidean_canonical_form --param alpha=ten
check "alpha=ten: exit 1, 'is not a float'" bash -c "[ $rc -eq 1 ] && grep -q \"alpha: 'ten' is not a float\" value.log"
run nofilter fig.ply x.ply --filter no_such_filter
check "an unknown filter: exit 1, names it" bash -c "[ $rc -eq 1 ] && grep -q \"no filter named 'no_such_filter'\" nofilter.log"
run nofile missing.ply x.ply --filter compute_conformal_factor
check "a missing input: exit 1, names it" bash -c "[ $rc -eq 1 ] && grep -q 'missing.ply does not exist' nofile.log"
check "no OUT written by any failure" test ! -e x.ply

# The plugin compiled for double precision (pymeshlab's), refused by the real MeshLab -------------------
wrong="$src/build/hosts/$suite/build/meshlab/wrong_precision/libfilter_canonical.so"
run wrong fig.ply x.ply --filter compute_conformal_factor --plugin "$wrong"
echo "    load_plugin(double plugin) -> $(grep -m1 -o 'libfilter_canonical.so has different.*' wrong.log)"
check "a double-precision plugin is refused by MeshLab $ml with its message" \
  bash -c "[ $rc -eq 1 ] && grep -q 'libfilter_canonical.so has different floating point precision from the running MeshLab version' wrong.log"

# A real articulated mesh ---------------------------------------------------------------------------------
data=${CANONFORM_DATA:-/work/data}/tosca_r5k/off
if [ -d "$data" ]; then
  for m in cat0 centaur0; do
    [ -f "$data/$m.off" ] || continue
    cp "$data/$m.off" "$m.off"
    start=$(date +%s.%N)
    run "real_$m" "$m.off" "${m}_canonical.ply" --filter generate_euclidean_canonical_form
    secs=$(echo "$(date +%s.%N) - $start" | bc)
    "$plycheck" "${m}_canonical.ply" "$m.off" > "real_${m}_ply.json"
    echo "    $m.off ($(json_get "real_${m}_ply.json" vertices) vertices): $(cat "real_$m.json") in $secs s"
    check "TOSCA $m.off: canonical form, same vertex count, exit 0" \
      bash -c "[ $rc -eq 0 ] && json real_${m}_ply.json \"j['same_vertex_count']\" && json real_$m.json \"j['converged']\""
  done
else
  echo "  (TOSCA meshes not found under $data: the real-mesh check is skipped)"
fi
finish
