#!/usr/bin/env bash
# The rules of the code that a reader can check without building it: no
# function over 80 lines (tools/function-lengths.py), no two modules that
# include each other (tools/module-cycles.py), no folder of the library that
# includes a header from a higher floor (tools/floor-order.py), and no message
# of the library that names a flag of the converter (the library names settings
# as its API does; the converter adds its flags, tools/levelfuse/FlagHints.cc).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/install-packages.sh python3 grep
failed=0
echo "== functions over 80 lines"
python3 tools/function-lengths.py --limit 80 src include tools || failed=1
echo "== modules that include each other"
python3 tools/module-cycles.py || failed=1
echo "== includes from a higher floor"
python3 tools/floor-order.py || failed=1
echo "== library messages that name a converter flag"
if grep -rnE '"[^"]*[ (]--[a-z][a-z-]+' src include --include=*.cc --include=*.h | grep -v '^src/python/'; then
  failed=1
fi
exit $failed
