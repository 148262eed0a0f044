#!/usr/bin/env bash
# Screenshots of MeshLab's GUI with the filter_canonical plugin, made headless under Xvfb:
#   docs/images/meshlab_filters_menu.png      Filters > Smoothing, Fairing and Deformation, open,
#                                             with "Euclidean canonical form" and "Geodesic canonical form"
#   docs/images/meshlab_canonical_form.png    the filter's parameter dialog after "Apply", with the
#                                             new layer in the layer list and the log line
#   tools/screenshot_gui.sh [--meshlab BIN] [--canonform BIN] [--out-dir DIR]
# The clicks are at fixed positions of MeshLab 2020.09's default layout on a 1600x1000 screen.
# The script checks that the plugin is installed for BIN (in BIN's ../lib/.../meshlab/plugins) and
# that the menu opened (the screenshot differs from the one before), and fails otherwise; look at
# the pictures to see the entries (positions are tied to that layout).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
meshlab=/usr/bin/meshlab
canonform=${CANONFORM_BUILD_DIR:-$here/build}/tools/canonform
outdir=$here/docs/images
while [ $# -gt 0 ]; do
  case "$1" in
    --meshlab) meshlab=$2; shift 2 ;;
    --canonform) canonform=$2; shift 2 ;;
    --out-dir) outdir=$2; shift 2 ;;
    *) echo "usage: $0 [--meshlab BIN] [--canonform BIN] [--out-dir DIR]" >&2; exit 2 ;;
  esac
done
for t in Xvfb xdotool import convert; do
  command -v $t >/dev/null || { echo "$0: $t missing (run tools/setup.sh)" >&2; exit 1; }
done
plugin="$(dirname "$(readlink -f "$meshlab")")/../lib/x86_64-linux-gnu/meshlab/plugins/libfilter_canonical.so"
[ -f "$plugin" ] || { echo "$0: the plugin is not installed for $meshlab ($plugin); run tools/install.sh" >&2; exit 1; }

work=$(mktemp -d); mkdir -p "$outdir"
display=:$((90 + RANDOM % 50))
cleanup() { kill "${ml_pid:-}" "${x_pid:-}" 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
Xvfb "$display" -screen 0 1600x1000x24 -nolisten tcp >/dev/null 2>&1 & x_pid=$!
export DISPLAY=$display
sleep 1
"$canonform" generate "$work/figure.ply" --vertices 5000 --pose 4
"$meshlab" "$work/figure.ply" > "$work/meshlab.log" 2>&1 & ml_pid=$!
xdotool search --sync --name "MeshLab" >/dev/null
sleep 4
click() {  # x y: a small two-step move first, so that sub-menus open reliably
  xdotool mousemove $(($1 - 6)) "$2"; sleep 0.3; xdotool mousemove "$1" "$2" click 1; sleep 1
}
hover() { xdotool mousemove $(($1 - 40)) "$2"; sleep 0.3; xdotool mousemove "$1" "$2"; sleep 1.2; }
import -window root "$work/before.png"
click 121 11            # Filters
hover 243 236           # Smoothing, Fairing and Deformation
import -window root "$work/menu.png"
if [ "$(compare -metric AE "$work/before.png" "$work/menu.png" null: 2>&1 || true)" = "0" ]; then
  echo "$0: the Filters menu did not open" >&2; exit 1
fi
convert "$work/menu.png" -crop 1066x720+0+0 +repage -strip "$outdir/meshlab_filters_menu.png"
click 621 311           # Euclidean canonical form (its parameter dialog opens)
click 297 598           # Apply
sleep 2
import -window root "$work/applied.png"
convert "$work/applied.png" -crop 1066x720+0+0 +repage -strip "$outdir/meshlab_canonical_form.png"
click 104 598           # Close the dialog
echo "screenshots: $outdir/meshlab_filters_menu.png $outdir/meshlab_canonical_form.png"
