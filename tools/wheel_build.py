#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Assembles the portable wheel (tools/package.sh --wheel, inside the bullseye root filesystem).

    wheel_build.py OUT_DIR --package PKG_DIR --tool CANONFORM --scripts DIR... --tag TAG
                   --flavour NAME PLUGIN.so PLUGIN.so [--flavour ...]
    wheel_build.py OUT_DIR --windows --package PKG_DIR --tool canonform.exe

PKG_DIR: the Python package the build assembled (BUILD/python/canonform: the modules, _version.py,
__init__.pyi, py.typed, lib/libcanonform.so). CANONFORM: the tool. Each --flavour: a plugin folder
name (pymeshlab2022.2, ...) and its two plugins. Writes OUT_DIR/canonform-VERSION-TAG.whl:

  canonform/*.py, __init__.pyi, py.typed   the package
  canonform/lib/libcanonform.so            the C API (RUNPATH $ORIGIN)
  canonform/lib/*-XXXXXXXX.so*             every library they need beyond the C and C++ runtime (and,
                                           for the plugins, what pymeshlab's process has: its
                                           libmeshlab-common.so and Qt 5), renamed with a hash of
                                           their content (tools/portable_bundle.py), RUNPATH $ORIGIN
  canonform/bin/canonform                  the tool (RUNPATH $ORIGIN/../lib); the console script
                                           `canonform` (canonform._cli:main) runs it
  canonform/plugins/FLAVOUR/*.so           the pymeshlab plugins (RUNPATH $ORIGIN/../../lib)
  canonform/plugins/scripts/*.mlx          the filters' default scripts
  canonform-VERSION.dist-info/             METADATA, WHEEL, entry_points.txt, LICENSE, RECORD

One copy of each library serves all of them. The zip's bytes depend only on the files (sorted
names, fixed time stamps: the newest input's, modes 755 for programs and libraries, 644 else).
Prints the wheel's path.

--windows (the MinGW-w64 build, tools/build.sh --windows: target windows_wheel) writes
OUT_DIR/canonform-VERSION-py3-none-win_amd64.whl: the same package files, canonform/lib/canonform.dll
and canonform/bin/canonform.exe, as built (linked statically against the C and C++ runtime, they
import only Windows system DLLs: tests/windows/imports_test.py), no plugins (MeshLab's Windows
plugins need MSVC).
"""
import argparse
import base64
import hashlib
import os
import shutil
import sys
import tempfile
import time
import zipfile

sys.dont_write_bytecode = True  # no __pycache__ written into the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import portable_bundle  # noqa: E402

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUMMARY = "Euclidean canonical forms of non-rigid meshes and view-based 3D shape retrieval, with numpy"


def record_hash(data):
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def metadata(version, system="POSIX :: Linux"):
    description = open(os.path.join(HERE, "docs", "python.md"), encoding="utf-8").read()
    return (f"Metadata-Version: 2.1\nName: canonform\nVersion: {version}\nSummary: {SUMMARY}\n"
            "License: GPL-3.0-or-later\nRequires-Python: >=3.9\nRequires-Dist: numpy\n"
            "Classifier: Programming Language :: Python :: 3\nClassifier: Programming Language :: C++\n"
            f"Classifier: Operating System :: {system}\nClassifier: Topic :: Scientific/Engineering\n"
            "Description-Content-Type: text/markdown\n\n" + description)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--package", required=True)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--scripts", nargs="+", default=[])
    ap.add_argument("--tag", default=None, help="default: py3-none-manylinux_2_31_x86_64 (win_amd64 with --windows)")
    ap.add_argument("--windows", action="store_true", help="the Windows wheel: canonform.dll and canonform.exe")
    ap.add_argument("--flavour", nargs=3, action="append", default=[], metavar=("NAME", "PLUGIN", "PLUGIN"))
    a = ap.parse_args()
    if a.windows and (a.flavour or a.scripts):
        ap.error("--windows: no plugins (MeshLab's Windows plugins need MSVC)")
    if a.tag is None:
        a.tag = "py3-none-win_amd64" if a.windows else "py3-none-manylinux_2_31_x86_64"
    ns = {}
    exec(open(os.path.join(a.package, "_version.py"), encoding="utf-8").read(), ns)
    version = ns["__version__"]
    lib_name = "canonform.dll" if a.windows else "libcanonform.so"
    tool_name = "canonform.exe" if a.windows else "canonform"
    inputs = [os.path.join(a.package, "lib", lib_name), a.tool] + [p for f in a.flavour for p in f[1:]]
    epoch = max(int(os.stat(p).st_mtime) for p in inputs)

    with tempfile.TemporaryDirectory(dir=a.out) as stage:
        pkg = os.path.join(stage, "canonform")
        shutil.copytree(a.package, pkg, ignore=shutil.ignore_patterns("__pycache__", "lib"))
        libdir = os.path.join(pkg, "lib")
        binaries = [(inputs[0], os.path.join(libdir, lib_name)), (a.tool, os.path.join(pkg, "bin", tool_name))]
        for name, *plugins in a.flavour:
            binaries += [(p, os.path.join(pkg, "plugins", name, os.path.basename(p))) for p in plugins]
        if a.windows:  # nothing to bundle: they import only system DLLs
            for src, dst in binaries:
                os.makedirs(os.path.dirname(dst), exist_ok=True)
                shutil.copyfile(src, dst)
        else:
            portable_bundle.bundle(binaries, libdir, portable_bundle.DEFAULT_ALLOWED, "canonform/lib",
                                   log=lambda line: print(line, file=sys.stderr))
        scripts = os.path.join(pkg, "plugins", "scripts")
        if a.scripts:
            os.makedirs(scripts, exist_ok=True)
        for d in a.scripts:
            for f in sorted(os.listdir(d)):
                if f.endswith(".mlx"):
                    shutil.copyfile(os.path.join(d, f), os.path.join(scripts, f))
        info = f"canonform-{version}.dist-info"
        os.makedirs(os.path.join(stage, info))
        extra = {
            "METADATA": metadata(version, "Microsoft :: Windows" if a.windows else "POSIX :: Linux"),
            "WHEEL": f"Wheel-Version: 1.0\nGenerator: canonform tools/wheel_build.py\nRoot-Is-Purelib: false\nTag: {a.tag}\n",
            "entry_points.txt": "[console_scripts]\ncanonform = canonform._cli:main\n",
            "LICENSE": open(os.path.join(HERE, "LICENSE"), encoding="utf-8").read(),
        }
        for name, text in extra.items():
            with open(os.path.join(stage, info, name), "w", encoding="utf-8") as f:
                f.write(text)

        files = sorted(os.path.relpath(os.path.join(d, f), stage).replace(os.sep, "/")
                       for d, _, fs in os.walk(stage) for f in fs)
        record = []
        wheel = os.path.join(a.out, f"canonform-{version}-{a.tag}.whl")
        stamp = time.gmtime(max(epoch, 315532800))[:6]  # zip's dates start in 1980
        with zipfile.ZipFile(wheel + ".tmp", "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
            def add(name, data, mode):
                zi = zipfile.ZipInfo(name, stamp)
                zi.external_attr = (0o100000 | mode) << 16
                zi.compress_type = zipfile.ZIP_DEFLATED
                z.writestr(zi, data)
            for name in files:
                path = os.path.join(stage, name)
                data = open(path, "rb").read()
                executable = data[:4] == b"\x7fELF" or data[:2] == b"MZ"  # ELF or PE (.exe, .dll)
                add(name, data, 0o755 if executable else 0o644)
                record.append(f"{name},{record_hash(data)},{len(data)}")
            record.append(f"{info}/RECORD,,")
            add(f"{info}/RECORD", ("\n".join(record) + "\n").encode(), 0o644)
        os.replace(wheel + ".tmp", wheel)
    print(f"[wheel] {wheel}: {os.path.getsize(wheel) // 1024} KiB", file=sys.stderr)
    print(wheel)
    return 0


if __name__ == "__main__":
    sys.exit(main())
