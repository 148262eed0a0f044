#!/usr/bin/env bash
# The Debian package of the plugins for this machine's MeshLab 2020.09 (tools/package.sh),
# installed as the README says (apt install ./FILE.deb): the plugins and their scripts land in
# MeshLab's own plugin folder, and the system's meshlabserver runs a filter from there. The
# package is removed afterwards if it was not installed before the test. Needs root.
#   package_test.sh SOURCE_DIR BUILD_DIR CANONFORM PLYCHECK WORKDIR
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); plycheck=$(realpath "$4"); work=$5
. "$(dirname "$0")/lib.sh"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
name=canonform-plugins-meshlab2020
plugins=/usr/lib/x86_64-linux-gnu/meshlab/plugins

echo "Debian package $name on this machine"
deb=$("$src/tools/package.sh" --build-dir "$build")
check "tools/package.sh wrote $(basename "$deb")" test -f "$deb"
dpkg-deb -f "$deb" Depends > depends.txt
check "depends on MeshLab 2020.09 exactly and the linked libraries ($(cut -c1-90 depends.txt)...)" \
  bash -c "grep -q 'meshlab (>= 2020.09~), meshlab (<< 2020.10~)' depends.txt && grep -q libqt5core5 depends.txt"
dpkg-deb -c "$deb" | awk '{print $6}' > contents.txt
check "holds both plugins and the meshlabserver scripts under $plugins" \
  bash -c "grep -qx .$plugins/libfilter_canonical.so contents.txt && grep -qx .$plugins/libfilter_viewdescriptor.so contents.txt &&
           grep -qx .$plugins/filter_canonical/euclidean_canonical_form.mlx contents.txt"
check "holds its licence (/usr/share/doc/$name/copyright, GPL-3.0+)" \
  bash -c "grep -qx ./usr/share/doc/$name/copyright contents.txt"
check "its version is the tool's ($("$cf" --version))" \
  bash -c "[ \"canonform \$(dpkg-deb -f '$deb' Version)\" = \"\$('$cf' --version)\" ]"

before=$(dpkg-query -W -f='${Status}' "$name" 2>/dev/null || true)
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --reinstall "$deb" > apt.log 2>&1
check "apt-get install ./$(basename "$deb")" bash -c "dpkg-query -W -f='\${Status}' $name | grep -q 'install ok installed'"
"$cf" generate fig.ply --vertices 2500 --pose 4 > /dev/null
xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/meshlabserver -i fig.ply -o cf.ply -m vq \
  -s "$plugins/filter_canonical/conformal_factor.mlx" > mls.log 2>&1
"$plycheck" cf.ply > cf.json 2>/dev/null
check "the system's meshlabserver runs 'Conformal factor' from the installed package (quality in [0, 1])" \
  json cf.json "j['vertices'] > 2000 and j['quality_min'] == 0 and abs(j['quality_max'] - 1) < 1e-6"
if ! echo "$before" | grep -q "install ok installed"; then
  DEBIAN_FRONTEND=noninteractive apt-get remove -y -qq "$name" > remove.log 2>&1
  check "removed again (it was not installed before the test)" test ! -e "$plugins/libfilter_canonical.so"
fi
finish
