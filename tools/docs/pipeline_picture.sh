#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The picture of the pipeline on the documentation's home page, drawn from the tool's real output:
#   mesh -> conformal factor -> feature points -> canonical form -> 66 depth views -> descriptor
#   (one bag-of-features histogram per view) -> distances (clock matching) to the other models.
# A small procedural collection (two body types in five poses, 4000 vertices) goes through
# `canonform retrieve --method euclidean-N`; the standard figure's fifth pose is the model shown, and
# the distance panel is the run's matrix.
#   tools/docs/pipeline_picture.sh OUT.png [CANONFORM]      (default: build/apps/canonform)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out=${1:?usage: $0 OUT.png [CANONFORM]}
cf=$(realpath "${2:-$here/build/apps/canonform}")
out=$(realpath -m "$out")
work=$(mktemp -d /tmp/canonform-pipeline.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$cf" generate --collection coll --vertices 4000 --poses 5 --classes standard,long-arms > /dev/null
"$cf" retrieve --dataset coll --out run --method euclidean-N --words 300 > retrieve.log 2>&1 ||
  { cat retrieve.log >&2; exit 1; }
mesh=coll/meshes/standard_4.ply
[ -f "$mesh" ] || { echo "$0: $mesh: not in the generated collection" >&2; ls coll/meshes >&2; exit 1; }
name=$(basename "${mesh%.*}")
form=$(find run/euclidean-N/forms -name "$name.*" | head -n 1)
desc=$(find run/euclidean-N/descriptors -name "$name.*" | head -n 1)
"$cf" conformal "$mesh" cf.ply > /dev/null
"$cf" features "$mesh" fp.ply > /dev/null
"$cf" picture mesh.png "$mesh" --size 300 > /dev/null
"$cf" picture panels.png cf.ply --points fp.ply --canonical "$form" --size 300 > /dev/null
"$cf" views "$form" views > /dev/null
/usr/bin/python3 "$here/tools/docs/pipeline_picture.py" "$out" mesh.png panels.png views/contact_sheet.png "$desc" \
  run/euclidean-N/distances.csv run/euclidean-N/models.csv coll/labels.csv "$name"
echo "$out"
