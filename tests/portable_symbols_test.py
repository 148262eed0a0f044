#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The pymeshlab 2023.12 plugins, compiled against MeshLab 2025.07's headers (cmake/MeshLabPortable.cmake),
leave undefined only MeshLab symbols that 2025.07's meshlab-common exports.

    portable_symbols_test.py LIBMESHLAB_COMMON_2025D.so LIBMESHLAB_COMMON_2025_FLOAT.so ARCHIVE.tar.gz...

For each plugin of the pymeshlab2023.12 and pymeshlab2025.7 archives: its undefined dynamic symbols
without a version (glibc, libstdc++ and Qt 5 version theirs) and not defined by a library of the
archive are MeshLab's; each must be exported by the first libmeshlab-common.so (double, built from
2025.07's source). Against the second (MeshLab 2025.07 in single precision, forky's) some must be
missing (RichFloat's constructor takes a float there): the check can fail. Names alone do not show
object layouts (the 2025.07-header plugins' 28-31 MeshLab names are all in 2022.02's library too);
the layouts rest on the comparison of MeshLab's sources in cmake/MeshLabPortable.cmake.
"""
import re
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

from check_report import Report


def nm(path, defined):
    out = subprocess.run(["nm", "-D", "--defined-only" if defined else "--undefined-only", str(path)],
                         check=True, capture_output=True, text=True).stdout
    names = set()
    for line in out.splitlines():
        f = line.split()
        if not f:
            continue
        kind, name = f[-2], f[-1]
        if defined:
            names.add(name.split("@")[0])
        elif kind == "U" and "@" not in name:
            names.add(name)
    return names


def main(argv):
    double, single, archives = nm(argv[0], True), nm(argv[1], True), argv[2:]
    report = Report()
    for archive in archives:
        m = re.search(r"-(pymeshlab(2023\.12|2025\.7))-linux", Path(archive).name)
        if not m:
            continue
        host = m.group(1)
        with tempfile.TemporaryDirectory() as tmp:
            with tarfile.open(archive) as t:
                t.extractall(tmp)
            top = next(Path(tmp).iterdir())
            bundled = set()
            for lib in (top / "canonform.libs").glob("*.so*"):
                bundled |= nm(lib, True)
            for plugin in sorted(top.glob("libfilter_*.so")):
                meshlab = nm(plugin, False) - bundled
                missing = sorted(meshlab - double)
                ok = bool(meshlab) and not missing
                report.check(ok, f"{host} {plugin.name}: " +
                             (f"all {len(meshlab)} undefined MeshLab symbols exported by 2025.07's double meshlab-common"
                              if ok else f"{len(missing)} of {len(meshlab)} not exported: {missing[:5]}"))
                wrong = sorted(meshlab - single)
                report.check(bool(wrong), f"{host} {plugin.name} against the single-precision library: "
                                          f"{len(wrong)} missing, as they must be (e.g. {wrong[:1]})")
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
