#!/usr/bin/env python3
"""The pymeshlab 2023.12 plugins, compiled against MeshLab 2025.07's headers (cmake/MeshLabPortable.cmake),
leave undefined only MeshLab symbols that 2025.07's meshlab-common exports.

    portable_symbols_test.py LIBMESHLAB_COMMON_2025.so ARCHIVE.tar.gz...

For each plugin of the pymeshlab2023.12 and pymeshlab2025.7 archives: its undefined dynamic symbols
without a version (glibc, libstdc++ and Qt 5 version theirs) and not defined by a library of the
archive are MeshLab's; each must be exported by the given libmeshlab-common.so (built from 2025.07's
source). The pymeshlab2022.2 archive's plugins, compiled against 2022.02's headers, must leave some
undefined that 2025.07's library lacks: the check can fail.
"""
import re
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path


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
    common, archives = argv[0], argv[1:]
    exported = nm(common, True)
    passed = failed = 0
    for archive in archives:
        m = re.search(r"-(pymeshlab20[0-9.]+)-linux", Path(archive).name)
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
                missing = sorted(meshlab - exported)
                if host == "pymeshlab2022.2":
                    ok = bool(missing)
                    what = (f"{len(missing)} of its {len(meshlab)} MeshLab symbols are not in 2025.07's meshlab-common "
                            f"(as it must be: 2022.02's headers), e.g. {missing[:2]}")
                else:
                    ok = not missing
                    what = (f"all {len(meshlab)} undefined MeshLab symbols exported by 2025.07's meshlab-common"
                            if ok else f"{len(missing)} not exported: {missing[:5]}")
                print(f"  {'ok  ' if ok else 'FAIL'} {host} {plugin.name}: {what}")
                passed += ok
                failed += not ok
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
