#!/usr/bin/env bash
# Runs one of the add-on's headless checks in Blender 3.4:
#   bash run_addon_script.sh NAME CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]
# runs tests/blender/NAME.py (addon_ui: import, export, Bake, Apply, Compare,
# unregister; addon_errors: every error report) with CLOTHBAKE_EXE, SOURCE_DIR
# and a temp work folder as arguments. Fails when a check fails, and when
# Blender printed a Python traceback anywhere: an operator that raised
# instead of reporting prints one, whatever it returned.
set -u

if [ $# -lt 3 ] || [ $# -gt 4 ]; then
  echo "usage: bash run_addon_script.sh NAME CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]" >&2
  exit 2
fi
name=$1 clothbake=$2 source=$3 blender=${4:-$(command -v blender)}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -f "$here/$name.py" ] || fail "no check script $here/$name.py"
[ -n "$blender" ] && [ -x "$blender" ] || fail "Blender executable not found"
[ -x "$clothbake" ] || fail "clothbake executable not found: $clothbake"
[ -f "$source/blender_addon/clothbake/__init__.py" ] || fail "no add-on under $source/blender_addon"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/$name.XXXXXX") || fail "mktemp -d failed"
trap 'rm -rf "$tmp"' EXIT

# Blender's user scripts/config go to the temp folder: the test neither reads
# nor writes the user's Blender set-up.
mkdir -p "$tmp/user_scripts" "$tmp/user_config" "$tmp/work"
start=$(date +%s)
BLENDER_USER_SCRIPTS="$tmp/user_scripts" BLENDER_USER_CONFIG="$tmp/user_config" \
  "$blender" -b --factory-startup --python-exit-code 1 \
  -P "$here/$name.py" -- "$clothbake" "$source" "$tmp/work" >"$tmp/blender.log" 2>&1
rc=$?
# Keep the checks and errors; drop Cycles' per-tile progress lines.
grep -v -E '^ *(Fra:|Saved:|Time:)|^$' "$tmp/blender.log"
echo "Blender exit status $rc after $(( $(date +%s) - start )) s"

[ "$rc" -eq 0 ] || fail "$name checks failed (exit status $rc; see above)"
if grep -q "Traceback" "$tmp/blender.log"; then
  fail "Blender printed a Python traceback (see above)"
fi
echo "PASS: blender.$name"
