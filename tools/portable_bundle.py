#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Makes a plugin folder self-contained, as auditwheel does for a wheel (tools/package.sh --portable).

    portable_bundle.py OUT_DIR PLUGIN.so... [--libs NAME] [--allow SONAME...]

Copies each plugin into OUT_DIR and every shared library it needs, recursively, into OUT_DIR/NAME
(default canonform.libs), except the libraries the host process already has loaded (--allow: by
default libmeshlab-common.so, Qt5 Core/Gui/Widgets/OpenGL/Xml/Network and the C/C++ runtime). Each
copied library gets a soname of its own, <name>-<first 8 hex digits of its SHA-256>.so<suffix>
(libtbb.so.2 -> libtbb-1a2b3c4d.so.2), and every NEEDED entry that named it is rewritten, so that a
library of the same name that another module of the process loaded (numpy's OpenBLAS, torch's
libgomp, opencv-python's OpenCV) is never taken for it and the other way round. RUNPATHs: the
plugins $ORIGIN/NAME, the bundled libraries $ORIGIN; nothing names a path of the build machine.
Libraries are found as the dynamic loader of the build system finds them (ldconfig -p). Uses
readelf (binutils) and patchelf. Prints one line per bundled library (original -> new, size).
"""
import argparse
import hashlib
import os
import re
import shutil
import subprocess
import sys

# What a MeshLab or pymeshlab process already has: pymeshlab's wheel and MeshLab's AppImage carry
# libmeshlab-common.so and Qt 5.15; libc, libstdc++ and libgcc_s come from the user's system.
DEFAULT_ALLOWED = [
    "libmeshlab-common.so",
    "libQt5Core.so.5", "libQt5Gui.so.5", "libQt5Widgets.so.5", "libQt5OpenGL.so.5", "libQt5Xml.so.5",
    "libQt5Network.so.5",
    "libc.so.6", "libm.so.6", "libdl.so.2", "libpthread.so.0", "librt.so.1", "libstdc++.so.6", "libgcc_s.so.1",
    "ld-linux-x86-64.so.2",
]


def dynamic(path):
    """(soname, [needed], [runpath entries]) of an ELF file, from readelf -d."""
    out = subprocess.run(["readelf", "-dW", path], check=True, capture_output=True, text=True).stdout
    soname, needed, runpath = None, [], []
    for line in out.splitlines():
        m = re.search(r"\((NEEDED|SONAME|RUNPATH|RPATH)\)\s+.*\[(.*)\]", line)
        if not m:
            continue
        kind, value = m.groups()
        if kind == "NEEDED":
            needed.append(value)
        elif kind == "SONAME":
            soname = value
        else:
            runpath += [p for p in value.split(":") if p]
    return soname, needed, runpath


def ldconfig_map():
    """soname -> path of the x86-64 libraries the dynamic loader knows (ldconfig -p)."""
    out = subprocess.run(["ldconfig", "-p"], check=True, capture_output=True, text=True).stdout
    found = {}
    for line in out.splitlines()[1:]:
        m = re.match(r"\s*(\S+) \(([^)]*)\) => (\S+)", line)
        if m and "x86-64" in m.group(2) and m.group(1) not in found:
            found[m.group(1)] = m.group(3)
    return found


def unique_name(soname, path):
    digest = hashlib.sha256(open(path, "rb").read()).hexdigest()[:8]
    m = re.match(r"^(.*?)(\.so(\..*)?)$", soname)
    if not m:
        raise SystemExit(f"portable_bundle: cannot name a copy of {soname}")
    return f"{m.group(1)}-{digest}{m.group(2)}"


def patchelf(*args):
    subprocess.run(["patchelf", *args], check=True)


def bundle(binaries, libdir, allowed, libs_name=None, log=print):
    """Copies each (source, destination) binary and every shared library they need, recursively,
    into `libdir` (except `allowed`), with unique sonames and RUNPATHs: each binary
    $ORIGIN/<libdir relative to its folder>, each library $ORIGIN. Binaries are stripped
    (--strip-unneeded). Returns the copied libraries' paths. `libs_name` names libdir in the log."""
    allowed = set(allowed)
    known = ldconfig_map()
    libs_name = libs_name or os.path.basename(libdir)
    os.makedirs(libdir, exist_ok=True)

    # 1. Walk NEEDED from the binaries, breadth first: soname -> path of the library it names.
    bundled, queue = {}, []
    for src, _ in binaries:
        queue += [(n, src) for n in dynamic(src)[1]]
    while queue:
        name, who = queue.pop(0)
        if name in allowed or name in bundled:
            continue
        path = known.get(name)
        if path is None:
            raise SystemExit(f"portable_bundle: {who} needs {name}, which the dynamic loader does not find here")
        bundled[name] = os.path.realpath(path)
        queue += [(n, path) for n in dynamic(path)[1]]

    # 2. Copy with unique sonames; RUNPATH $ORIGIN; NEEDED rewritten.
    renamed = {name: unique_name(name, path) for name, path in bundled.items()}
    if len(set(renamed.values())) != len(renamed):
        raise SystemExit("portable_bundle: two libraries would get the same name")
    copies = []
    for name, path in sorted(bundled.items()):
        dest = os.path.join(libdir, renamed[name])
        shutil.copyfile(path, dest)
        os.chmod(dest, 0o755)
        patchelf("--set-soname", renamed[name], dest)
        copies.append(dest)
        log(f"  {name} ({path}) -> {libs_name}/{renamed[name]} ({os.path.getsize(path) // 1024} KiB)")
    outs = []
    for src, dest in binaries:
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(src, dest)
        os.chmod(dest, 0o755)
        subprocess.run(["strip", "--strip-unneeded", dest], check=True)
        outs.append(dest)
    for f in copies + outs:
        needed = dynamic(f)[1]
        for n in needed:
            if n in renamed:
                patchelf("--replace-needed", n, renamed[n], f)
        if f in outs:
            if any(n in renamed for n in needed):
                rel = os.path.relpath(libdir, os.path.dirname(f))
                patchelf("--set-rpath", "$ORIGIN" if rel == "." else "$ORIGIN/" + rel, f)
            else:
                patchelf("--remove-rpath", f)
        else:
            patchelf("--set-rpath", "$ORIGIN", f)
    if not copies and not os.listdir(libdir):
        os.rmdir(libdir)
    return copies


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("plugins", nargs="+")
    ap.add_argument("--libs", default="canonform.libs")
    ap.add_argument("--allow", nargs="*", default=DEFAULT_ALLOWED)
    a = ap.parse_args()
    bundle([(p, os.path.join(a.out, os.path.basename(p))) for p in a.plugins], os.path.join(a.out, a.libs), a.allow,
           a.libs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
