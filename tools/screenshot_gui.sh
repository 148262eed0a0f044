#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Screenshots of MeshLab's GUI with the filter_canonical plugin, made headless under Xvfb:
#   docs/images/meshlab_filters_menu.png      Filters > Smoothing, Fairing and Deformation, open,
#                                             with "Euclidean canonical form" and "Geodesic canonical form"
#   docs/images/meshlab_canonical_form.png    the filter's parameter dialog after "Apply", with the
#                                             new layer in the layer list and the log line
#   tools/screenshot_gui.sh [--meshlab BIN] [--canonform BIN | --figure MESH] [--out-dir DIR]
#                           [--layout 2020|2022|2025] [--name PREFIX]
# The clicks are at fixed positions of MeshLab's default layout on a 1600x1000 screen: --layout 2020
# for MeshLab 2020.09 (the default), 2022 and 2025 for MeshLab 2022.02 and 2025.07 (the same menus;
# 2025.07's dialog is taller: it names the filter's pymeshlab call). The
# pictures are PREFIXfilters_menu.png and PREFIXcanonical_form.png (PREFIX default "meshlab_").
# tools/screenshot_hosts.sh runs this inside the trixie and forky root filesystems.
# The script checks that the plugin is installed for BIN (in BIN's ../lib/.../meshlab/plugins) and
# that the menu opened (the screenshot differs from the one before), and fails otherwise; look at
# the pictures to see the entries (positions are tied to that layout).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
meshlab=/usr/bin/meshlab
canonform=${CANONFORM_BUILD_DIR:-$here/build}/apps/canonform
outdir=$here/docs/images
figure="" layout=2020 name=meshlab_
while [ $# -gt 0 ]; do
  case "$1" in
    --meshlab) meshlab=$2; shift 2 ;;
    --canonform) canonform=$2; shift 2 ;;
    --figure) figure=$2; shift 2 ;;
    --out-dir) outdir=$2; shift 2 ;;
    --layout) layout=$2; shift 2 ;;
    --name) name=$2; shift 2 ;;
    *) echo "usage: $0 [--meshlab BIN] [--canonform BIN | --figure MESH] [--out-dir DIR] [--layout 2020|2022|2025] [--name PREFIX]" >&2; exit 2 ;;
  esac
done
# positions: Filters menu, Smoothing sub-menu, "Euclidean canonical form", Apply, Close; picture height
case "$layout" in
  2020) filters=(121 11) smoothing=(243 236) entry=(621 311) apply=(297 598) close=(104 598) height=720 ;;
  2022) filters=(121 11) smoothing=(240 217) entry=(590 286) apply=(623 623) close=(441 623) height=760 ;;
  2025) filters=(121 11) smoothing=(240 217) entry=(590 286) apply=(623 683) close=(441 683) height=760 ;;
  *) echo "$0: --layout 2020, 2022 or 2025" >&2; exit 2 ;;
esac
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
if [ -n "$figure" ]; then cp "$figure" "$work/figure.ply"; else "$canonform" generate "$work/figure.ply" --vertices 5000 --pose 4; fi
"$meshlab" "$work/figure.ply" > "$work/meshlab.log" 2>&1 & ml_pid=$!
xdotool search --sync --name "MeshLab" >/dev/null
sleep 4
click() {  # x y: a small two-step move first, so that sub-menus open reliably
  xdotool mousemove $(($1 - 6)) "$2"; sleep 0.3; xdotool mousemove "$1" "$2" click 1; sleep 1
}
hover() { xdotool mousemove $(($1 - 40)) "$2"; sleep 0.3; xdotool mousemove "$1" "$2"; sleep 1.2; }
import -window root "$work/before.png"
click "${filters[@]}"           # Filters
hover "${smoothing[@]}"         # Smoothing, Fairing and Deformation
import -window root "$work/menu.png"
if [ "$(compare -metric AE "$work/before.png" "$work/menu.png" null: 2>&1 || true)" = "0" ]; then
  echo "$0: the Filters menu did not open" >&2; exit 1
fi
convert "$work/menu.png" -crop 1066x${height}+0+0 +repage -strip "$outdir/${name}filters_menu.png"
click "${entry[@]}"             # Euclidean canonical form (its parameter dialog opens)
click "${apply[@]}"             # Apply
sleep 2
import -window root "$work/applied.png"
convert "$work/applied.png" -crop 1066x${height}+0+0 +repage -strip "$outdir/${name}canonical_form.png"
click "${close[@]}"             # Close the dialog
echo "screenshots: $outdir/${name}filters_menu.png $outdir/${name}canonical_form.png"
