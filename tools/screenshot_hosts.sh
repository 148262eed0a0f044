#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Screenshots of the real MeshLab 2022.02 (Debian trixie) and 2025.07 (Debian forky) with our
# filters: tools/screenshot_gui.sh run in each root filesystem of tools/host.sh, where the plugins
# were built and apt-installed as a user there does, on a generated figure (5000 vertices, pose 4):
#   docs/images/meshlab2022_filters_menu.png    Filters > Smoothing, Fairing and Deformation open
#   docs/images/meshlab2022_canonical_form.png  "Euclidean canonical form"'s dialog after Apply
#   docs/images/meshlab2025_...                 the same in MeshLab 2025.07
#   tools/screenshot_hosts.sh [trixie|forky]...     (default: both; as root)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${CANONFORM_BUILD_DIR:-$here/build}
suites=("$@")
[ ${#suites[@]} -gt 0 ] || suites=(trixie forky)
[ -x "$build/apps/canonform" ] || { echo "$0: $build/apps/canonform missing: tools/build.sh first" >&2; exit 1; }
work=$(mktemp -d /tmp/canonform-screenshots.XXXXXX)  # /tmp is visible inside the root filesystems
trap 'rm -rf "$work"' EXIT
"$build/apps/canonform" generate "$work/figure.ply" --vertices 5000 --pose 4 > /dev/null
for suite in "${suites[@]}"; do
  case "$suite" in trixie) year=2022 ;; forky) year=2025 ;; *) echo "$0: trixie or forky" >&2; exit 2 ;; esac
  "$here/tools/host.sh" "$suite" "$here/tools/screenshot_gui.sh" --meshlab /usr/bin/meshlab --figure "$work/figure.ply" \
    --layout $year --name meshlab${year}_ --out-dir "$here/docs/images"
done
