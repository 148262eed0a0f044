# SPDX-License-Identifier: GPL-3.0-or-later
"""Every DLL a program of the Windows build imports is one of Windows' own (docs/windows.md) or
canonform.dll, shipped beside it, as `x86_64-w64-mingw32-objdump -p` lists its imports: MinGW's
runtime DLLs (libstdc++-6.dll, libgcc_s_seh-1.dll, libwinpthread-1.dll, libgomp-1.dll) must be
linked in statically. The check is first shown to refuse: a program built here against MinGW's DLLs.

usage: imports_test.py PROGRAM.exe|LIBRARY.dll...
"""
import os
import re
import subprocess
import sys
import tempfile

OBJDUMP = "x86_64-w64-mingw32-objdump"
CXX = "x86_64-w64-mingw32-g++-posix"
# DLLs that are part of every Windows 10 and 11 (lower case): the C runtimes, the kernel and the
# Win32 API sets a C++ program may reach through MinGW's runtime.
SYSTEM = {"kernel32.dll", "msvcrt.dll", "ucrtbase.dll", "advapi32.dll", "user32.dll", "shell32.dll", "ole32.dll",
          "ws2_32.dll", "bcrypt.dll", "ntdll.dll", "shlwapi.dll", "psapi.dll", "dbghelp.dll"}
API_SET = re.compile(r"^api-ms-win-[a-z0-9-]+\.dll$")
# The project's own DLL (the C API), shipped beside the programs that use it (the release zip).
SHIPPED = {"canonform.dll"}


def imports(path):
    out = subprocess.run([OBJDUMP, "-p", path], capture_output=True, text=True, check=True).stdout
    return sorted(set(re.findall(r"DLL Name: (\S+)", out)))


def foreign(dlls):
    return [d for d in dlls if d.lower() not in SYSTEM | SHIPPED and not API_SET.match(d.lower())]


def main(paths):
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "hello.cpp")
        with open(src, "w") as f:
            f.write("#include <iostream>\n#include <thread>\n"
                    "int main() { std::thread t([] { std::cout << 1; }); t.join(); }\n")
        dynamic = os.path.join(tmp, "dynamic.exe")
        subprocess.run([CXX, "-O1", src, "-o", dynamic], check=True)  # no -static: MinGW's DLLs
        bad = foreign(imports(dynamic))
        if bad:
            print(f"  ok   the check refuses a program linked against MinGW's DLLs ({', '.join(bad)})")
        else:
            print("  FAIL the check let a dynamically linked program through")
            failures += 1
    for p in paths:
        dlls = imports(p)
        bad = foreign(dlls)
        if bad:
            print(f"  FAIL {os.path.basename(p)} imports {', '.join(bad)} (not Windows' own nor shipped; imports: {', '.join(dlls)})")
            failures += 1
        else:
            print(f"  ok   {os.path.basename(p)} imports only Windows' own DLLs and canonform.dll: {', '.join(dlls)}")
    print(f"{len(paths) + 1 - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
