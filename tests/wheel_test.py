#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads the portable wheel (tools/package.sh --wheel) as pip and auditwheel would.

    wheel_test.py WHEEL [--max-mib 30]

Fails on any of:
  - a name that is not canonform-VERSION-py3-none-manylinux_2_31_x86_64.whl, a WHEEL file with
    another tag or Root-Is-Purelib true, METADATA without its name, version, numpy requirement,
    no console script `canonform = canonform._cli:main`;
  - a RECORD that does not list every file exactly once with its size and sha256 (as pip checks);
  - a missing part: the package's modules and stubs, lib/libcanonform.so, bin/canonform, both
    plugins of each pymeshlab flavour (2022.2, 2023.12, 2025.7) and the .mlx scripts; a CPython
    extension module (the package must serve every Python 3);
  - every ELF file, as the portable_elf test reads the archives: a symbol version newer than
    manylinux_2_31 allows (GLIBC 2.31, GLIBCXX 3.4.28, CXXABI 1.3.12); a RUNPATH not relative to
    $ORIGIN; a NEEDED library that is neither the C/C++ runtime nor in canonform/lib (the plugins
    may also need what pymeshlab's process has loaded: libmeshlab-common.so and Qt 5); a bundled
    library without a hashed soname, two with one soname; a library in the wrong folder;
  - the C library exporting anything but the C API's functions;
  - a wheel larger than --max-mib MiB.
Prints the sizes, the newest symbol versions and what is bundled.
"""
import base64
import csv
import hashlib
import io
import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

sys.dont_write_bytecode = True  # no __pycache__ written into the source tree
sys.path.insert(0, str(Path(__file__).parent))
from check_report import Report  # noqa: E402
from portable_elf_test import ALLOWED, dotted, is_elf, objdump  # noqa: E402

RUNTIME = {"libc.so.6", "libm.so.6", "libdl.so.2", "libpthread.so.0", "librt.so.1", "libstdc++.so.6", "libgcc_s.so.1",
           "ld-linux-x86-64.so.2"}
LIMITS = {"GLIBC": (2, 31), "GLIBCXX": (3, 4, 28), "CXXABI": (1, 3, 12)}
FLAVOURS = ["pymeshlab2022.2", "pymeshlab2023.12", "pymeshlab2025.7"]
PLUGINS = ["libfilter_canonical.so", "libfilter_viewdescriptor.so"]
MODULES = ["__init__.py", "__init__.pyi", "py.typed", "_version.py", "_library.py", "_support.py", "_meshes.py",
           "_views.py", "_retrieval.py", "_cli.py", "pymeshlab.py"]


def record_check(z, info):
    """A wheel's RECORD (zipfile z, dist-info folder info) as pip reads it: the names it lists, and
    those whose sha256 or size is wrong or that the wheel lacks."""
    names = set(z.namelist())
    rows = list(csv.reader(io.StringIO(z.read(f"{info}/RECORD").decode()))) if f"{info}/RECORD" in names else []
    bad = []
    for r in rows:
        if r[0] == f"{info}/RECORD":
            continue
        data = z.read(r[0]) if r[0] in names else None
        digest = "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode() if data is not None else ""
        if data is None or r[1] != digest or r[2] != str(len(data)):
            bad.append(r[0])
    return [r[0] for r in rows], bad


def main(argv):
    report = Report()
    wheel = Path(argv[0])
    max_mib = float(argv[argv.index("--max-mib") + 1]) if "--max-mib" in argv else 30.0

    def expect(ok, what):
        print(f"{'ok  ' if ok else 'FAIL'} {what}")
        report.count(ok)

    m = re.match(r"canonform-(\d+\.\d+\.\d+)-py3-none-manylinux_2_31_x86_64\.whl$", wheel.name)
    expect(m is not None, f"the wheel's name ({wheel.name})")
    version = m.group(1) if m else "?"
    size = wheel.stat().st_size
    expect(size <= max_mib * 2**20, f"size {size / 2**20:.1f} MiB (at most {max_mib:g} MiB)")
    z = zipfile.ZipFile(wheel)
    names = z.namelist()
    info = f"canonform-{version}.dist-info"
    read = lambda n: z.read(n).decode("utf-8")  # noqa: E731
    wheel_meta = read(f"{info}/WHEEL") if f"{info}/WHEEL" in names else ""
    expect("Tag: py3-none-manylinux_2_31_x86_64\n" in wheel_meta and "Root-Is-Purelib: false" in wheel_meta,
           "WHEEL: the tag py3-none-manylinux_2_31_x86_64, not purelib")
    meta = read(f"{info}/METADATA") if f"{info}/METADATA" in names else ""
    expect(f"Name: canonform\nVersion: {version}\n" in meta and "Requires-Dist: numpy" in meta,
           "METADATA: name, version, numpy")
    entry = read(f"{info}/entry_points.txt") if f"{info}/entry_points.txt" in names else ""
    expect(re.search(r"^\[console_scripts\]\ncanonform = canonform\._cli:main$", entry, re.M) is not None,
           "entry_points.txt: the console script canonform")

    # RECORD: every file once, sizes and hashes as pip checks them
    listed, bad = record_check(z, info)
    expect(sorted(listed) == sorted(names) and len(set(listed)) == len(listed) and not bad,
           f"RECORD lists the {len(names)} files once each, with their sizes and sha256 ({len(bad)} wrong)")

    wanted = [f"canonform/{f}" for f in MODULES] + ["canonform/lib/libcanonform.so", "canonform/bin/canonform"]
    wanted += [f"canonform/plugins/{fl}/{p}" for fl in FLAVOURS for p in PLUGINS]
    missing = [w for w in wanted if w not in names]
    scripts = [n for n in names if n.startswith("canonform/plugins/scripts/") and n.endswith(".mlx")]
    expect(not missing and len(scripts) == 5, f"the package, the library, the tool, 3 flavours' plugins, 5 scripts "
                                                f"(missing: {missing or 'none'})")
    expect(not [n for n in names if re.search(r"\.(cpython|abi3|pypy)[^/]*\.so$|\.pyd$", n)],
           "no CPython extension module")

    with tempfile.TemporaryDirectory() as tmp:
        z.extractall(tmp)
        root = Path(tmp)
        libdir = root / "canonform" / "lib"
        elves = sorted(p for p in root.rglob("*") if p.is_file() and is_elf(p))
        data = {p: objdump(p) for p in elves}
        sonames = {}
        failures = []
        for p, (_, soname, _, _) in data.items():
            rel = p.relative_to(root)
            if p.parent == libdir and p.name != "libcanonform.so":
                sonames.setdefault(soname, []).append(rel)
                if not soname or not re.search(r"-[0-9a-f]{8}\.so", soname):
                    failures.append(f"{rel}: soname {soname} is a name systems use (not renamed)")
            elif p.parent != libdir and p.suffix == ".so" and p.parent.parent.name != "plugins":
                failures.append(f"{rel}: a library outside canonform/lib")
        failures += [f"duplicate soname {s}: {ps}" for s, ps in sonames.items() if len(ps) > 1]
        newest = {}
        for p, (needed, _, runpath, versions) in data.items():
            rel = p.relative_to(root)
            plugin = p.parent.parent.name == "plugins"
            for r in runpath:
                if not r.startswith("$ORIGIN"):
                    failures.append(f"{rel}: RUNPATH {r} is not relative to $ORIGIN")
            for n in needed:
                if n in sonames or n in RUNTIME or (plugin and n in ALLOWED):
                    continue
                failures.append(f"{rel}: NEEDED {n} is neither the runtime{', pymeshlab' if plugin else ''} nor in canonform/lib")
            for kind, vs in versions.items():
                v = max(vs)
                newest[kind] = max(newest.get(kind, v), v)
                if v > LIMITS[kind]:
                    failures.append(f"{rel}: {kind}_{dotted(v)} is newer than manylinux_2_31's {kind}_{dotted(LIMITS[kind])}")
        for f in failures:
            print(f"     {f}")
        expect(not failures, f"{len(elves)} ELF files audited; newest " +
               ", ".join(f"{k}_{dotted(newest[k])}" for k in sorted(newest)))
        print(f"     bundled: {' '.join(sorted(s for s in sonames if s))}")
        table = subprocess.run(["objdump", "-T", str(libdir / "libcanonform.so")], capture_output=True, text=True).stdout
        exported = [l.split()[-1] for l in table.splitlines() if " g " in l and "*UND*" not in l and (" DF " in l or " DO " in l)]
        expect(len(exported) >= 30 and all(e.startswith("canonform_") for e in exported),
               f"libcanonform.so exports the C API only ({len(exported)} functions)")
        for part in ("canonform/lib", "canonform/bin", "canonform/plugins"):
            total = sum(f.stat().st_size for f in (root / part).rglob("*") if f.is_file())
            print(f"     {part}: {total / 2**20:.1f} MiB unpacked")
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
