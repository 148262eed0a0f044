#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The same results from every build of the plugins on the same mesh (the figure of 'canonform
# generate --vertices 2500 --pose 4', coordinates in float):
#   pymeshlab2022, pymeshlab2025   double: the pymeshlab harness (tests/pymeshlab_harness.cpp)
#   meshlab2020                    float: MeshLab 2020.09's meshlabserver (this machine)
#   meshlab2022 (trixie), meshlab2025 (forky)   float: canonform-meshlab in the real host (tools/host.sh)
# against the canonform tool (double): conformal factor and canonical form vertex by vertex to
# float precision, the same SMACOF iteration count and final stress, and the depth view descriptor.
#   same_results_test.sh SOURCE_DIR BUILD_DIR CANONFORM PLYCHECK WORKDIR
#       [--harness NAME HARNESS CANONICAL.so VIEW.so WRONG_PRECISION.so]... [--host SUITE]...
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); plycheck=$(realpath "$4"); work=$5
shift 5
harnesses=(); hosts=()
while [ $# -gt 0 ]; do
  case "$1" in
    --harness) harnesses+=("$2|$(realpath "$3")|$(realpath "$4")|$(realpath "$5")|$(realpath "$6")"); shift 6 ;;
    --host) hosts+=("$2"); shift 2 ;;
    *) echo "unknown argument $1"; exit 2 ;;
  esac
done
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
work=$(pwd)

echo "the same results from every build: ${#harnesses[@]} pymeshlab harness(es), meshlabserver 2020.09, ${#hosts[@]} host(s), the tool"
"$cf" generate fig.ply --vertices 2500 --pose 4 > /dev/null
"$cf" codebook cb.bin fig.ply --words 100 > /dev/null 2>&1
builds=()  # NAME|PRECISION|CF.ply|CANON.ply|OUTPUTS.json (iterations, final_stress)|DESCRIPTOR.cfvd

# The reference: the canonform tool (double)
"$cf" conformal fig.ply ref_cf.ply > /dev/null
"$cf" canonical fig.ply ref_canon.ply --json > ref_canon.json
"$cf" descriptor fig.ply ref.cfvd --codebook cb.bin > /dev/null 2>&1

# pymeshlab 2022.2 / 2025.7 (double): the harness applies every filter; its figure is ours
for h in "${harnesses[@]}"; do
  IFS='|' read -r name harness canon view wrong <<< "$h"
  "$harness" --plugin "$canon" --plugin "$view" --wrong-precision "$wrong" --vertices 2500 --pose 4 \
    --codebook "$work/cb.bin" --out "$name" > "$name.log" 2>&1
  check "$name harness passes: $(tail -n 1 "$name.log")" grep -q ' 0 failed$' "$name.log"
  "$plycheck" "$name/input.ply" fig.ply > "${name}_input.json"
  check "$name: the harness's figure is the mesh of 'canonform generate' (bit for bit)" \
    json "${name}_input.json" "j['same_vertex_count'] and j['max_position_diff'] == 0"
  /usr/bin/python3 -c "
import json, sys; h = json.load(open(sys.argv[1]))['generate_euclidean_canonical_form']
json.dump({'iterations': h['iterations'], 'final_stress': h['final_stress']}, open(sys.argv[2], 'w'))" \
    "$name/outputs.json" "${name}_ecf.json"
  builds+=("$name|double|$name/cf.ply|$name/canon.ply|${name}_ecf.json|$name/descriptor.cfvd")
done

# MeshLab 2020.09 (float): the real meshlabserver through a private prefix
"$src/tools/install.sh" --prefix "$work/prefix" --build-dir "$build" > install.log 2>&1
scripts="$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_canonical"
mls() { log=$1; shift; xvfb-run -a -s "-screen 0 1280x1024x24" "$work/prefix/bin/meshlabserver" "$@" > "$log" 2>&1; }
mls ml20_cf.log -i fig.ply -o ml20_cf.ply -m vq -s "$scripts/conformal_factor.mlx"
mls ml20_ecf.log -i fig.ply -o ml20_canon.ply -l 1 -m vq -s "$scripts/euclidean_canonical_form.mlx"
/usr/bin/python3 - ml20_ecf.log ml20_ecf.json <<'EOF'
import json, re, sys
m = re.search(r"(\d+) SMACOF iterations.*?stress ([0-9.eE+-]+) -> ([0-9.eE+-]+)", open(sys.argv[1], errors="replace").read())
json.dump({"iterations": int(m.group(1)), "final_stress": float(m.group(3)), "digits": 6} if m else {}, open(sys.argv[2], "w"))
EOF
sed -e "s|name=\"output_file\" type=\"RichString\" value=\"descriptor.cfvd\"|name=\"output_file\" type=\"RichString\" value=\"$work/ml20.cfvd\"|" \
    -e "s|name=\"codebook_file\" type=\"RichString\" value=\"\"|name=\"codebook_file\" type=\"RichString\" value=\"$work/cb.bin\"|" \
    "$work/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_viewdescriptor/depth_view_descriptor.mlx" > dv.mlx
mls ml20_dv.log -i fig.ply -s dv.mlx
builds+=("meshlab2020|float|ml20_cf.ply|ml20_canon.ply|ml20_ecf.json|ml20.cfvd")

# MeshLab 2022.02 (trixie) and 2025.07 (forky), float: canonform-meshlab in the real host
for suite in "${hosts[@]}"; do
  case "$suite" in trixie) name=meshlab2022 ;; forky) name=meshlab2025 ;; *) name=$suite ;; esac
  inside() { CANONFORM_HOST_PREPARE=0 "$src/tools/host.sh" "$suite" "$@"; }
  inside canonform-meshlab fig.ply "${name}_cf.ply" --filter compute_conformal_factor > "${name}_cf.json" 2> "${name}_cf.log"
  inside canonform-meshlab fig.ply "${name}_canon.ply" --filter generate_euclidean_canonical_form \
    > "${name}_ecf.json" 2> "${name}_ecf.log"
  inside canonform-meshlab fig.ply "${name}_dv.ply" --filter compute_depth_view_descriptor \
    --param "output_file=$work/$name.cfvd" --param "codebook_file=$work/cb.bin" --param seed=0 > "${name}_dv.json" 2> "${name}_dv.log"
  check "$name ($suite): canonform-meshlab ran the three filters" test -s "${name}_canon.ply" -a -s "$name.cfvd" -a -s "${name}_cf.ply"
  builds+=("$name|float|${name}_cf.ply|${name}_canon.ply|${name}_ecf.json|$name.cfvd")
done

# Every build against the tool ------------------------------------------------------------------
descriptors=(ref.cfvd)
for b in "${builds[@]}"; do
  IFS='|' read -r name precision cf_ply canon_ply ecf_json cfvd <<< "$b"
  "$plycheck" "$cf_ply" ref_cf.ply > "${name}_cf_vs_tool.json" 2>/dev/null
  "$plycheck" "$canon_ply" ref_canon.ply > "${name}_canon_vs_tool.json" 2>/dev/null
  # float builds store float coordinates and quality: agreement to float precision (the figure is ~2 units)
  if [ "$precision" = double ]; then tol=1e-6; else tol=1e-5; fi
  echo "    $name ($precision): conformal factor max |diff| $(json_get "${name}_cf_vs_tool.json" max_quality_diff)," \
       "canonical form max |diff| $(json_get "${name}_canon_vs_tool.json" max_position_diff)," \
       "iterations $(json_get "$ecf_json" iterations) (tool $(json_get ref_canon.json iterations))," \
       "final stress $(json_get "$ecf_json" final_stress) (tool $(json_get ref_canon.json final_stress))"
  check "$name: conformal factor = the tool's to $tol" \
    json "${name}_cf_vs_tool.json" "j['same_vertex_count'] and j['max_quality_diff'] < $tol"
  check "$name: canonical form = the tool's vertex by vertex to $tol (no alignment)" \
    json "${name}_canon_vs_tool.json" "j['same_vertex_count'] and j['max_position_diff'] < $tol"
  # the tool prints 6 significant digits; meshlabserver's log too
  check "$name: the same SMACOF iteration count and final stress as the tool" /usr/bin/python3 -c "
import json; b = json.load(open('$ecf_json')); t = json.load(open('ref_canon.json'))
assert b['iterations'] == t['iterations'] and abs(b['final_stress'] - t['final_stress']) <= 5e-6 * t['final_stress'], (b, t)"
  descriptors+=("$cfvd")
done
"$cf" distance dv.bin "${descriptors[@]}" > dv_dist.log 2>&1
/usr/bin/python3 - dv.bin.csv "${builds[@]}" <<'EOF' > dv.txt
import csv, sys
D = [[float(x) for x in r] for r in csv.reader(open(sys.argv[1]))]
for k, b in enumerate(sys.argv[2:], start=1):
    name, precision = b.split("|")[:2]
    ok = D[0][k] < 1e-6  # the figure's coordinates are floats: every build renders the same views
    print(f"{name} {precision} {D[0][k]:.6g} {ok}")
EOF
while read -r name precision d ok; do
  check "$name: depth view descriptor at clock-matching distance $d from the tool's (< 1e-6)" test "$ok" = True
done < dv.txt
finish
