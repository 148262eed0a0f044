# SPDX-License-Identifier: GPL-3.0-or-later
"""The pass/fail lines of the test scripts in tests/: one line per check ("  ok   WHAT" or
"  FAIL WHAT", a failure's detail on the next line), then "N passed, M failed"; the exit code is 0
only if something was checked and nothing failed."""


class Report:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, what, detail=""):
        """Prints and counts one check; returns ok."""
        print(f"  {'ok  ' if ok else 'FAIL'} {what}" + (f"\n       {detail}" if detail and not ok else ""))
        self.passed += bool(ok)
        self.failed += not ok
        return ok

    def count(self, ok):
        """Counts a check that printed its own lines."""
        self.passed += bool(ok)
        self.failed += not ok

    def exit_code(self):
        print(f"{self.passed} passed, {self.failed} failed")
        return 0 if self.failed == 0 and self.passed > 0 else 1
