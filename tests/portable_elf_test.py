#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads every ELF file of a portable archive (tools/package.sh --portable), as auditwheel checks a wheel.

    portable_elf_test.py ARCHIVE.tar.gz... [--refuses HOST PLUGIN.so... SCRIPTS_DIR...]

Fails on any of:
  - a symbol version newer than the oldest system of the archive's host has: glibc 2.31 and
    GLIBCXX_3.4.28 / CXXABI_1.3.12 (GCC 10) for pymeshlab 2022.2 and 2023.12 (wheels tagged
    manylinux_2_31, built on Ubuntu 20.04); glibc 2.35 and GLIBCXX_3.4.30 / CXXABI_1.3.13 for
    pymeshlab 2025.7 and MeshLab 2025.07 (manylinux_2_35, Ubuntu 22.04);
  - a RUNPATH or RPATH entry that is not relative to $ORIGIN (a path of the build machine);
  - a NEEDED library that is neither one the host process already has (libmeshlab-common.so, Qt 5
    Core/Gui/Widgets/OpenGL/Xml/Network, the C and C++ runtime) nor a library of the archive;
  - two libraries with the same soname, or a bundled library under a soname a system may have
    (every bundled soname carries the 8-hex-digit tag tools/portable_bundle.py gives it);
  - a missing plugin (libfilter_canonical.so, libfilter_viewdescriptor.so at the top), .mlx
    script or INSTALL.txt.
Prints per archive the newest symbol versions, the NEEDED libraries outside it and what it bundles.
--refuses: an archive for HOST made of plugins as built (today's bookworm plugins: build-folder
RUNPATH, OpenCV and TBB outside, bookworm's glibc) must fail on each of those three counts.
"""
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

from check_report import Report

ALLOWED = {
    "libmeshlab-common.so",
    "libQt5Core.so.5", "libQt5Gui.so.5", "libQt5Widgets.so.5", "libQt5OpenGL.so.5", "libQt5Xml.so.5",
    "libQt5Network.so.5",
    "libc.so.6", "libm.so.6", "libdl.so.2", "libpthread.so.0", "librt.so.1", "libstdc++.so.6", "libgcc_s.so.1",
    "ld-linux-x86-64.so.2",
}
# host in the archive's name -> newest GLIBC_, GLIBCXX_, CXXABI_ version allowed
LIMITS = {
    "pymeshlab2022.2": ((2, 31), (3, 4, 28), (1, 3, 12)),
    "pymeshlab2023.12": ((2, 31), (3, 4, 28), (1, 3, 12)),
    "pymeshlab2025.7": ((2, 35), (3, 4, 30), (1, 3, 13)),
    "meshlab2025.07": ((2, 35), (3, 4, 30), (1, 3, 13)),
}
SCRIPTS = {"conformal_factor.mlx", "feature_points.mlx", "euclidean_canonical_form.mlx",
           "geodesic_canonical_form.mlx", "depth_view_descriptor.mlx"}


def objdump(path):
    """NEEDED, SONAME, RUNPATH/RPATH entries and version references {prefix: [versions]} of an ELF file."""
    out = subprocess.run(["objdump", "-p", str(path)], check=True, capture_output=True, text=True).stdout
    needed, soname, runpath, versions = [], None, [], {}
    for line in out.splitlines():
        f = line.split()
        if len(f) == 2 and f[0] == "NEEDED":
            needed.append(f[1])
        elif len(f) == 2 and f[0] == "SONAME":
            soname = f[1]
        elif len(f) == 2 and f[0] in ("RUNPATH", "RPATH"):
            runpath += [p for p in f[1].split(":") if p]
        m = re.match(r"\s+0x[0-9a-f]+ 0x[0-9a-f]+ \d+ (GLIBC|GLIBCXX|CXXABI)_([0-9.]+)$", line)
        if m:
            versions.setdefault(m.group(1), []).append(tuple(int(x) for x in m.group(2).split(".")))
    return needed, soname, runpath, versions


def is_elf(path):
    with open(path, "rb") as f:
        return f.read(4) == b"\x7fELF"


def dotted(v):
    return ".".join(map(str, v))


def check(archive):
    """(failures, summary lines) of one archive."""
    failures, summary = [], []
    name = Path(archive).name
    m = re.match(r"canonform-plugins-[^-]+-(.+)-linux-x86_64\.tar\.gz$", name)
    if not m or m.group(1) not in LIMITS:
        return [f"{name}: not a portable archive's name"], summary
    host = m.group(1)
    limits = dict(zip(("GLIBC", "GLIBCXX", "CXXABI"), LIMITS[host]))
    with tempfile.TemporaryDirectory() as tmp:
        with tarfile.open(archive) as t:
            t.extractall(tmp)
        tops = list(Path(tmp).iterdir())
        if len(tops) != 1 or tops[0].name != name[: -len(".tar.gz")]:
            return [f"{name}: does not hold exactly one folder named like the archive"], summary
        top = tops[0]
        for p in ("libfilter_canonical.so", "libfilter_viewdescriptor.so", "INSTALL.txt"):
            if not (top / p).is_file():
                failures.append(f"missing {p}")
        missing = SCRIPTS - {p.name for p in (top / "scripts").glob("*.mlx")}
        if missing:
            failures.append(f"missing scripts: {sorted(missing)}")
        elves = sorted(p for p in top.rglob("*") if p.is_file() and not p.is_symlink() and is_elf(p))
        info = {p: objdump(p) for p in elves}
        sonames = {}
        for p, (_, soname, _, _) in info.items():
            if p.parent != top:  # a bundled library
                if soname is None:
                    failures.append(f"{p.relative_to(top)} has no soname")
                    continue
                sonames.setdefault(soname, []).append(p)
                if not re.search(r"-[0-9a-f]{8}\.so", soname):
                    failures.append(f"{p.relative_to(top)}: soname {soname} is a name systems use (not renamed)")
        for soname, paths in sonames.items():
            if len(paths) > 1:
                failures.append(f"duplicate soname {soname}: {[str(p.relative_to(top)) for p in paths]}")
        newest = {}
        outside = set()
        for p, (needed, _, runpath, versions) in info.items():
            rel = p.relative_to(top)
            for r in runpath:
                if not r.startswith("$ORIGIN"):
                    failures.append(f"{rel}: RUNPATH {r} is not relative to $ORIGIN")
            for n in needed:
                if n in ALLOWED:
                    outside.add(n)
                elif n not in sonames:
                    failures.append(f"{rel}: NEEDED {n} is neither allowed outside nor in the archive")
            for kind, vs in versions.items():
                v = max(vs)
                newest[kind] = max(newest.get(kind, v), v)
                if v > limits[kind]:
                    failures.append(f"{rel}: {kind}_{dotted(v)} is newer than {kind}_{dotted(limits[kind])} ({host})")
        summary.append(f"{name}: {len(elves)} ELF files; newest " +
                       ", ".join(f"{k}_{dotted(newest[k])} (limit {dotted(limits[k])})" for k in sorted(newest)))
        summary.append(f"  NEEDED outside: {' '.join(sorted(outside))}")
        summary.append(f"  bundled: {' '.join(sorted(sonames)) or '(none)'}")
    return failures, summary


def refuses(host, plugins, scripts_dirs):
    """An archive for HOST made of PLUGINS as built (not bundled) must fail, with a RUNPATH, a NEEDED
    and a symbol version reason: proof that the check sees what it is meant to see."""
    with tempfile.TemporaryDirectory() as tmp:
        name = f"canonform-plugins-0-{host}-linux-x86_64"
        top = Path(tmp, name)
        (top / "scripts").mkdir(parents=True)
        for p in plugins:
            shutil.copy(p, top)
        for d in scripts_dirs:
            for mlx in Path(d).glob("*.mlx"):
                shutil.copy(mlx, top / "scripts")
        (top / "INSTALL.txt").write_text("test\n")
        archive = Path(tmp, name + ".tar.gz")
        with tarfile.open(archive, "w:gz") as t:
            t.add(top, arcname=name)
        failures, _ = check(str(archive))
    for f in failures[:8]:
        print(f"  (expected) {f}")
    reasons = {"RUNPATH": "RUNPATH", "NEEDED": "NEEDED", "symbol version": "is newer than"}
    seen = [k for k, r in reasons.items() if any(r in f for f in failures)]
    ok = len(seen) == len(reasons)
    print(f"{'ok  ' if ok else 'FAIL'} an archive of the plugins as built ({' '.join(Path(p).name for p in plugins)}) "
          f"is refused: {len(failures)} failures, of kinds {seen}")
    return ok


def main(argv):
    report = Report()
    if "--refuses" in argv:
        i = argv.index("--refuses")
        argv, (host, *rest) = argv[:i], argv[i + 1:]
        plugins = [p for p in rest if p.endswith(".so")]
        report.count(refuses(host, plugins, [p for p in rest if not p.endswith(".so")]))
    for archive in argv:
        failures, summary = check(archive)
        print("\n".join(summary))
        for f in failures:
            print(f"  FAIL {f}")
        print(f"{'ok  ' if not failures else 'FAIL'} {Path(archive).name}")
        report.count(not failures)
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
