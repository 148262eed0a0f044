# SPDX-License-Identifier: GPL-3.0-or-later
"""The `canonform` command of the wheel (its console-script entry point): runs the canonform tool
the wheel carries, canonform/bin/canonform, with the same arguments, in place of this process."""
import os
import subprocess
import sys


def tool_path():
    name = "canonform.exe" if sys.platform == "win32" else "canonform"
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", name)


def main():
    exe = tool_path()
    if not os.path.isfile(exe):
        sys.exit(f"canonform: this install of the Python package has no canonform tool ({exe}): it comes with the "
                 "wheel, or from a build of the repository (build/apps/canonform)")
    if os.name == "posix":
        os.execv(exe, [exe] + sys.argv[1:])
    sys.exit(subprocess.call([exe] + sys.argv[1:]))


if __name__ == "__main__":
    main()
