# SPDX-License-Identifier: GPL-3.0-or-later
"""Puts the licence line `SPDX-License-Identifier: GPL-3.0-or-later` into every source file of the
repository, or checks that every one has it.

usage: /usr/bin/python3 tools/spdx.py [--check] [ROOT]

Source files are the files git tracks (or, outside a git checkout, every file under ROOT) ending in
.h, .cpp, .py, .sh or .cmake, every CMakeLists.txt, and executable scripts starting with "#!" (.ci/run); not
external/ (Debian's MeshLab sources), not data or generated files. The line goes first, as a comment
of the file's language: after a "#!" line where there is one. --check changes nothing and lists the
files without it (exit status 1 if there is one): the test licence.spdx. A new file gets its line by
running this script.
"""
import os
import subprocess
import sys

TAG = "SPDX-License-Identifier: GPL-3.0-or-later"
SLASH = (".h", ".cpp", ".hpp", ".cc", ".c")
HASH = (".py", ".sh", ".cmake")


def sources(root):
    try:
        files = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True, check=True,
                               text=True).stdout.split("\0")
    except (subprocess.CalledProcessError, FileNotFoundError):
        files = [os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs]
    for rel in sorted(f for f in files if f):
        if rel.startswith(("external/", "build")):
            continue
        path = os.path.join(root, rel)
        if not os.path.isfile(path) or os.path.islink(path):
            continue
        name = os.path.basename(rel)
        if name.endswith(SLASH):
            yield rel, "// "
        elif name.endswith(HASH) or name == "CMakeLists.txt":
            yield rel, "# "
        elif "." not in name and os.access(path, os.X_OK):
            with open(path, "rb") as f:
                if f.read(2) == b"#!":
                    yield rel, "# "


def main():
    args = [a for a in sys.argv[1:] if a != "--check"]
    check = "--check" in sys.argv[1:]
    root = os.path.realpath(args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    missing, changed, total = [], 0, 0
    for rel, comment in sources(root):
        total += 1
        path = os.path.join(root, rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        accepted = {comment + TAG} | ({"/* " + TAG + " */"} if comment == "// " else set())  # C89 comments in C
        if any(line.strip() in accepted for line in text.splitlines()[:3]):
            continue
        if check:
            missing.append(rel)
            continue
        lines = text.splitlines(keepends=True)
        at = 1 if lines and lines[0].startswith("#!") else 0
        lines.insert(at, comment + TAG + "\n")
        mode = os.stat(path).st_mode
        with open(path, "w", encoding="utf-8") as f:
            f.write("".join(lines))
        os.chmod(path, mode)
        changed += 1
    if check:
        for rel in missing:
            print(f"spdx: {rel}: no '{TAG}' line in its first lines (tools/spdx.py adds it)")
        print(f"spdx: {total} source files, {len(missing)} without the licence line")
        sys.exit(1 if missing else 0)
    print(f"spdx: {total} source files, the licence line added to {changed}")


if __name__ == "__main__":
    main()
