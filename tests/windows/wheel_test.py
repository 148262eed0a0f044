# SPDX-License-Identifier: GPL-3.0-or-later
"""The Windows wheel (tools/wheel_build.py --windows, target windows_wheel), as far as it can be
tried without a Windows Python: its name and tags, its RECORD (every file, each hash and size), the
Python package the same files as python/canonform/, canonform.dll and canonform.exe the bytes of
the build's, importing only Windows system DLLs (imports_test.py), no Linux library or plugin in it,
and the package's own loading logic, run on the unpacked wheel, finding its canonform.dll and
canonform.exe where they are. (The DLL through the C API under Wine: windows.c_api.)

usage: wheel_test.py WHEEL SOURCE_DIR canonform.dll canonform.exe
"""
import importlib.util
import os
import sys
import tempfile
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path[:0] = [os.path.dirname(HERE), HERE]  # tests/ first: its wheel_test, not this one
import imports_test  # noqa: E402
from check_report import Report  # noqa: E402
from wheel_test import record_check  # noqa: E402


def main():
    wheel, source, dll, exe = sys.argv[1:5]
    report = Report()

    def check(what, ok):
        report.check(ok, what)
    check(f"{os.path.basename(wheel)} is tagged py3-none-win_amd64", wheel.endswith("-py3-none-win_amd64.whl"))
    z = zipfile.ZipFile(wheel)
    names = z.namelist()
    info = [n for n in names if n.endswith(".dist-info/WHEEL")]
    check("one .dist-info with a WHEEL file", len(info) == 1)
    if len(info) != 1:
        return report.exit_code()
    dist = info[0].rsplit("/", 1)[0]
    meta = z.read(f"{dist}/WHEEL").decode()
    check("WHEEL: Tag py3-none-win_amd64, not purelib",
          "Tag: py3-none-win_amd64\n" in meta and "Root-Is-Purelib: false\n" in meta)
    check("entry_points.txt: the console script canonform = canonform._cli:main",
          "canonform = canonform._cli:main" in z.read(f"{dist}/entry_points.txt").decode())
    check("METADATA names Windows", "Operating System :: Microsoft :: Windows" in z.read(f"{dist}/METADATA").decode())

    listed, bad = record_check(z, dist)
    check("RECORD lists every file of the wheel once", sorted(set(listed)) == sorted(names) and len(listed) == len(names))
    check(f"RECORD: every hash and size right ({', '.join(bad) or 'all'})", not bad)

    pkg_src = os.path.join(source, "python", "canonform")
    py = sorted(f for f in os.listdir(pkg_src) if f.endswith(".py") or f == "py.typed")
    same = [f for f in py if f"canonform/{f}" in names and z.read(f"canonform/{f}") == open(os.path.join(pkg_src, f), "rb").read()]
    check(f"the package: the {len(py)} files of python/canonform/ as they are", same == py)
    check("... with _version.py and the stubs __init__.pyi", "canonform/_version.py" in names and "canonform/__init__.pyi" in names)
    check("canonform/lib/canonform.dll: the build's, byte for byte",
          "canonform/lib/canonform.dll" in names and z.read("canonform/lib/canonform.dll") == open(dll, "rb").read())
    check("canonform/bin/canonform.exe: the build's, byte for byte",
          "canonform/bin/canonform.exe" in names and z.read("canonform/bin/canonform.exe") == open(exe, "rb").read())
    stray = [n for n in names if n.endswith(".so") or ".so." in n or "/plugins/" in n]
    check(f"no Linux library and no plugin ({', '.join(stray) or 'none'})", not stray)

    with tempfile.TemporaryDirectory() as tmp:
        z.extractall(tmp)
        binaries = [os.path.join(tmp, "canonform", "lib", "canonform.dll"), os.path.join(tmp, "canonform", "bin", "canonform.exe")]
        bad = {os.path.basename(b): imports_test.foreign(imports_test.imports(b)) for b in binaries}
        check(f"the wheel's DLL and program import only Windows system DLLs and canonform.dll ({bad})",
              not any(bad.values()))
        # The package's loading logic, as Windows' Python would run it (sys.platform "win32"),
        # on the unpacked wheel: the library it tries first is the wheel's DLL.
        spec = importlib.util.spec_from_file_location("canonform_library", os.path.join(tmp, "canonform", "_library.py"))
        library = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(library)
        first = library.candidates(os.path.join(tmp, "canonform"), "win32", {})[0]
        check(f"the package looks for {os.path.relpath(first, tmp)} on Windows, which the wheel holds",
              os.path.isfile(first) and first.endswith(os.path.join("lib", "canonform.dll")))
        spec = importlib.util.spec_from_file_location("canonform_cli", os.path.join(tmp, "canonform", "_cli.py"))
        cli = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(cli)
        platform = sys.platform
        try:
            cli.sys.platform = "win32"
            tool = cli.tool_path()
        finally:
            cli.sys.platform = platform
        check(f"the console script runs {os.path.relpath(tool, tmp)} on Windows, which the wheel holds", os.path.isfile(tool))
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main())
