# SPDX-License-Identifier: GPL-3.0-or-later
"""The Windows release archive (apps/CMakeLists.txt, target windows_zip): one folder named as the
archive, holding exactly canonform.exe, canonform.dll, canonform.h and LICENSE, each the same bytes
as the file it was made from.

usage: zip_test.py ARCHIVE.zip CANONFORM.EXE CANONFORM.DLL CANONFORM.H LICENSE
"""
import os
import sys
import zipfile


def main(archive, *sources):
    failures = 0

    def check(ok, what, detail=""):
        nonlocal failures
        print(f"  {'ok  ' if ok else 'FAIL'} {what}" + (f"\n       {detail}" if detail and not ok else ""))
        failures += not ok

    top = os.path.basename(archive)[: -len(".zip")]
    with zipfile.ZipFile(archive) as z:
        check(z.testzip() is None, f"{os.path.basename(archive)} reads back without a CRC error")
        files = sorted(n for n in z.namelist() if not n.endswith("/"))
        want = sorted(f"{top}/{os.path.basename(s)}" for s in sources)
        check(files == want, f"it holds {', '.join(os.path.basename(s) for s in sources)} in {top}/",
              f"holds: {', '.join(files)}")
        for s in sources:
            name = f"{top}/{os.path.basename(s)}"
            if name in files:
                with open(s, "rb") as f:
                    check(z.read(name) == f.read(), f"{os.path.basename(s)} is the same bytes as the build's")
    print(f"{'failed' if failures else 'passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
