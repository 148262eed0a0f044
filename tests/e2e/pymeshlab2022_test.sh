#!/usr/bin/env bash
# The same results from both builds on the same mesh: the MeshLab 2022.02 / pymeshlab 2022.2
# plugins (double, through tests/meshlab2022_harness.cpp) against the MeshLab 2020.09 plugins
# (float, in the real meshlabserver) and the canonform tool (double), on the generated figure the
# harness writes (input.ply: exactly the mesh of 'canonform generate --vertices 2500 --pose 4').
#   pymeshlab2022_test.sh SOURCE_DIR BUILD_DIR CANONFORM PLYCHECK HARNESS CANON22.so VIEW22.so FLOAT22.so WORKDIR
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); plycheck=$(realpath "$4")
harness=$(realpath "$5"); canon22=$(realpath "$6"); view22=$(realpath "$7"); float22=$(realpath "$8"); work=$9
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)

echo "pymeshlab 2022.2 build (double) against the MeshLab 2020.09 build (float) and the tool (double)"
"$cf" generate fig.ply --vertices 2500 --pose 4
"$cf" codebook cb.bin fig.ply --words 100 2>/dev/null
"$harness" --plugin "$canon22" --plugin "$view22" --wrong-precision "$float22" --vertices 2500 --pose 4 \
  --codebook "$work/cb.bin" --out h > harness.log 2>&1
check "harness (load_plugin, every filter by its Python name) passes: $(tail -n 1 harness.log)" \
  grep -q ' 0 failed$' harness.log
"$plycheck" h/input.ply fig.ply > input.json
check "the harness's figure is the mesh of 'canonform generate' (bit for bit)" \
  json input.json "j['same_vertex_count'] and j['max_position_diff'] == 0"

"$src/tools/install.sh" --prefix "$work/prefix" --build-dir "$build" > install.log 2>&1
scripts="$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_canonical"
mls() {  # MeshLab 2020.09's meshlabserver with the float plugins; output in $log
  log=$1; shift
  xvfb-run -a -s "-screen 0 1280x1024x24" "$work/prefix/bin/meshlabserver" "$@" > "$log" 2>&1
}

# Conformal factor: quality of 2022 (double) vs 2020 (float) vs the tool (double)
mls cf.log -i h/input.ply -o ml_cf.ply -m vq -s "$scripts/conformal_factor.mlx"
"$plycheck" h/cf.ply ml_cf.ply > cf_2020.json
"$cf" conformal fig.ply ref_cf.ply
"$plycheck" h/cf.ply ref_cf.ply > cf_tool.json
echo "    conformal factor, max |2022 - 2020| = $(json_get cf_2020.json max_quality_diff), max |2022 - tool| = $(json_get cf_tool.json max_quality_diff)"
check "conformal factor: 2022 (double) = 2020 (float) to float precision (max diff < 1e-5)" \
  json cf_2020.json "j['same_vertex_count'] and j['max_quality_diff'] < 1e-5"
check "conformal factor: 2022 = the tool (double) to 1e-6 (the harness wrote 9 digits)" \
  json cf_tool.json "j['same_vertex_count'] and j['max_quality_diff'] < 1e-6"

# Euclidean canonical form: positions (same frame, no alignment) and the SMACOF figures
mls ecf.log -i h/input.ply -o ml_canon.ply -l 1 -m vq -s "$scripts/euclidean_canonical_form.mlx"
"$plycheck" h/canon.ply ml_canon.ply > canon_2020.json
"$cf" canonical fig.ply ref_canon.ply --json > ref_canon_out.json
"$plycheck" h/canon.ply ref_canon.ply > canon_tool.json
"$plycheck" h/canon.ply fig.ply > canon_input.json
echo "    canonical form, max |2022 - 2020| = $(json_get canon_2020.json max_position_diff), aligned RMS $(json_get canon_2020.json aligned_rms); max |2022 - tool| = $(json_get canon_tool.json max_position_diff); figure size: aligned RMS to the input $(json_get canon_input.json aligned_rms)"
check "canonical form: 2022 (double) = 2020 (float) vertex by vertex to 1e-5 (figure ~2 units), quality to 1e-5" \
  json canon_2020.json "j['same_vertex_count'] and j['max_position_diff'] < 1e-5 and j['max_quality_diff'] < 1e-5"
check "canonical form: 2022 = the tool (double; its PLY holds floats) to 1e-6" \
  json canon_tool.json "j['same_vertex_count'] and j['max_position_diff'] < 1e-6"
/usr/bin/python3 - "$work" > smacof.txt 2>&1 <<'EOF'
import json, re, sys
w = sys.argv[1]
h = json.load(open(w + "/h/outputs.json"))["generate_euclidean_canonical_form"]
t = json.load(open(w + "/ref_canon_out.json"))
log = open(w + "/ecf.log", errors="replace").read()
m = re.search(r"(\d+) SMACOF iterations.*?stress ([0-9.eE+-]+) -> ([0-9.eE+-]+)", log)
it20, s0_20, s1_20 = int(m.group(1)), float(m.group(2)), float(m.group(3))
print(f"    SMACOF: 2022 {h['iterations']} iterations, stress {h['initial_stress']:.9g} -> {h['final_stress']:.9g}; "
      f"2020 (log) {it20}, {s0_20:.6g} -> {s1_20:.6g}; tool {t['iterations']}, {t['initial_stress']:.9g} -> {t['final_stress']:.9g}")
# the tool and the log print 6 significant digits
ok_tool = h["iterations"] == t["iterations"] and abs(h["final_stress"] - t["final_stress"]) <= 5e-6 * t["final_stress"]
ok_2020 = abs(h["iterations"] - it20) <= 2 and abs(h["final_stress"] - s1_20) <= 1e-4 * s1_20
print("tool", ok_tool); print("2020", ok_2020)
EOF
cat smacof.txt | head -1
check "SMACOF dict: same iterations and final stress as the tool (double; to its 6 printed digits)" grep -qx "tool True" smacof.txt
check "SMACOF dict: final stress within 1e-4 (relative) and iterations within 2 of 2020's log (float)" grep -qx "2020 True" smacof.txt

# Depth view descriptor: 2022's file and 2020's file are near (clock-matching distance)
vscripts="$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_viewdescriptor"
sed -e "s|name=\"output_file\" type=\"RichString\" value=\"descriptor.cfvd\"|name=\"output_file\" type=\"RichString\" value=\"$work/ml.cfvd\"|" \
    -e "s|name=\"codebook_file\" type=\"RichString\" value=\"\"|name=\"codebook_file\" type=\"RichString\" value=\"$work/cb.bin\"|" \
    "$vscripts/depth_view_descriptor.mlx" > dv.mlx
mls dv.log -i h/input.ply -s dv.mlx
"$cf" descriptor fig.ply tool.cfvd --codebook cb.bin
"$cf" distance dv.bin h/descriptor.cfvd ml.cfvd tool.cfvd > dv_dist.log 2>&1
echo "    descriptor distances (2022, 2020, tool): $(tr '\n' ' ' < dv.bin.csv)"
check "depth view descriptor: 2022 = the tool (distance 0), 2020 near (< 1; 66 views)" /usr/bin/python3 -c "
import csv; D = [[float(x) for x in r] for r in csv.reader(open('dv.bin.csv'))]; assert D[0][2] < 1e-6 and D[0][1] < 1, D"

# The wrong-precision plugin: MeshLab's message, as pymeshlab would raise it
check "single-precision plugin refused: $(grep -o 'MLException: .*precision.*' harness.log | head -n 1)" \
  grep -q "has different floating point precision from the running MeshLab version" harness.log
finish
