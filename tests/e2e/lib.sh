# SPDX-License-Identifier: GPL-3.0-or-later
# Helpers of the end-to-end tests (sourced).
fails=0
passes=0
pass() { passes=$((passes + 1)); echo "  ok   $*"; }
fail() { fails=$((fails + 1)); echo "  FAIL $*"; }
# check DESCRIPTION COMMAND...: passes when the command succeeds
check() { local d=$1; shift; if "$@"; then pass "$d"; else fail "$d"; fi; }
# json FILE EXPRESSION: evaluates a Python expression on the JSON object `j` read from FILE
json() { /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1" 2>/dev/null; }
finish() {
  echo "$passes passed, $fails failed"
  [ "$fails" -eq 0 ]
}
# json_get FILE KEY: prints one value of a JSON object
json_get() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1])).get(sys.argv[2]))" "$1" "$2" 2>/dev/null; }
