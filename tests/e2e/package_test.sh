#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Debian package of the plugins for this machine's MeshLab 2020.09 (tools/package.sh),
# installed as the README says (apt install ./FILE.deb): the plugins and their scripts land in
# MeshLab's own plugin folder, and the system's meshlabserver runs a filter from there; then the
# package is removed. All of it happens in a throwaway copy-on-write view of this machine
# (tools/sandbox.sh), so the machine's MeshLab plugin folder, its dpkg database and whatever
# tools/install.sh put there (README command 1) are left exactly as they were: checked at the end.
# Needs root.
#   package_test.sh SOURCE_DIR BUILD_DIR CANONFORM PLYCHECK WORKDIR
set -u
src=$(realpath "$1"); build=$(realpath "$2"); cf=$(realpath "$3"); plycheck=$(realpath "$4"); work=$(realpath -m "$5")
name=canonform-plugins-meshlab2020
plugins=/usr/lib/x86_64-linux-gnu/meshlab/plugins
if [ "${CANONFORM_IN_SANDBOX:-0}" != 1 ]; then
  # On the machine: the state the test must not change, then the test itself inside the sandbox.
  . "$(dirname "$0")/lib.sh"
  rm -rf "$work"; mkdir -p "$work"
  state() { { find "$plugins" -printf '%p %s %T@ %m\n' 2>/dev/null | sort; md5sum /var/lib/dpkg/status;
              ls /var/lib/dpkg/info | md5sum; }; }
  state > "$work/machine_before.txt"
  "$src/tools/sandbox.sh" --bind "$build" --bind "$work" bash "$(realpath "$0")" "$@"
  rc=$?
  state > "$work/machine_after.txt"
  check "inside the sandbox: the package test passed (exit $rc)" test $rc -eq 0
  check "the machine's MeshLab plugin folder and dpkg database are as before the test" \
    cmp -s "$work/machine_before.txt" "$work/machine_after.txt"
  finish
  exit $?
fi
. "$(dirname "$0")/lib.sh"
cd "$work" || exit 1

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

DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --reinstall "$deb" > apt.log 2>&1
check "apt-get install ./$(basename "$deb")" bash -c "dpkg-query -W -f='\${Status}' $name | grep -q 'install ok installed'"
"$cf" generate fig.ply --vertices 2500 --pose 4 > /dev/null
xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/meshlabserver -i fig.ply -o cf.ply -m vq \
  -s "$plugins/filter_canonical/conformal_factor.mlx" > mls.log 2>&1
"$plycheck" cf.ply > cf.json 2>/dev/null
check "the system's meshlabserver runs 'Conformal factor' from the installed package (quality in [0, 1])" \
  json cf.json "j['vertices'] > 2000 and j['quality_min'] == 0 and abs(j['quality_max'] - 1) < 1e-6"
DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq "$name" > remove.log 2>&1
check "apt-get purge $name removes the plugins" test ! -e "$plugins/libfilter_canonical.so"
finish
