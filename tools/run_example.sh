#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# README command 1: the main job on a built-in example.
# Sets up and builds only what the example uses (tools/build.sh --example: the packages of the
# build and of meshlabserver under Xvfb, the installed MeshLab's source; the library, the canonform
# tool and the plugins - command 2, tools/run_tests.sh, adds the rest), installs the plugins (as root
# into MeshLab's plugin folder, else into a private MeshLab prefix under build/), generates a
# procedural articulated figure, and runs the three filters in MeshLab's own meshlabserver. Writes
# into example_output/:
#   figure.ply            the generated figure (pose 4, ~8000 vertices)
#   conformal_factor.ply  layer 0: the figure with the conformal factor as vertex quality/colour
#   feature_points.ply    layer 1: the feature points (point cloud, quality = conformal factor)
#   canonical_form.ply    layer 2: the Euclidean canonical form
#   canonical_form.png    the figure, its feature points and its canonical form side by side
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
out=${CANONFORM_EXAMPLE_DIR:-$here/example_output}
vertices=${CANONFORM_EXAMPLE_VERTICES:-8000}

CANONFORM_BUILD_DIR=$build "$here/tools/build.sh" --example
if [ "$(id -u)" -eq 0 ]; then
  "$here/tools/install.sh" --build-dir "$build"
  meshlabserver=/usr/bin/meshlabserver
  scripts=/usr/lib/x86_64-linux-gnu/meshlab/plugins/filter_canonical
else
  "$here/tools/install.sh" --build-dir "$build" --prefix "$build/prefix"
  meshlabserver=$build/prefix/bin/meshlabserver
  scripts=$build/prefix/lib/x86_64-linux-gnu/meshlab/plugins/filter_canonical
fi
canonform=$build/apps/canonform

mkdir -p "$out"
echo "[example] generating a procedural articulated figure (~$vertices vertices, pose 4)"
"$canonform" generate "$out/figure.ply" --vertices "$vertices" --pose 4

# One script with the three shipped filters; the feature points also go to a new layer.
{ echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
  for s in conformal_factor feature_points euclidean_canonical_form; do
    sed -n '/<filter/,/<\/filter>/p' "$scripts/$s.mlx"
  done | sed 's/name="add_layer" type="RichBool" value="false"/name="add_layer" type="RichBool" value="true"/'
  echo '</FilterScript>'; } > "$out/pipeline.mlx"

echo "[example] meshlabserver: Conformal factor -> Feature points -> Euclidean canonical form"
if ! xvfb-run -a -s "-screen 0 1280x1024x24" "$meshlabserver" -i "$out/figure.ply" \
      -o "$out/conformal_factor.ply" -l 0 -m vq vc \
      -o "$out/feature_points.ply" -l 1 -m vq \
      -o "$out/canonical_form.ply" -l 2 -m vq \
      -s "$out/pipeline.mlx" > "$out/meshlabserver.log" 2>&1; then
  tail -20 "$out/meshlabserver.log"
  echo "[example] meshlabserver failed (log: $out/meshlabserver.log)" >&2
  exit 1
fi
grep -E "^LOG: [0-9]+ " "$out/meshlabserver.log" | sed -E "s/^LOG: [0-9]+ /[meshlab] /"

"$canonform" picture "$out/canonical_form.png" "$out/conformal_factor.ply" \
  --points "$out/feature_points.ply" --canonical "$out/canonical_form.ply" --size 420 2>/dev/null
echo "[example] done: $out/canonical_form.ply and $out/canonical_form.png"
