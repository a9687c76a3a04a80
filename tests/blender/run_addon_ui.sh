#!/usr/bin/env bash
# CTest blender.addon_ui: the add-on's operators in headless Blender 3.4
# (addon_ui.py): import, export (accepted by clothbake render), Bake, Apply,
# Compare, error reports and a clean unregister.
#
#   bash run_addon_ui.sh CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]
#
# Exit status 0 when every check passes, non-zero otherwise.
set -u

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: bash run_addon_ui.sh CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]" >&2
  exit 2
fi
clothbake=$1 source=$2 blender=${3:-$(command -v blender)}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -n "$blender" ] && [ -x "$blender" ] || fail "Blender executable not found"
[ -x "$clothbake" ] || fail "clothbake executable not found: $clothbake"
[ -f "$source/blender_addon/clothbake/__init__.py" ] || fail "no add-on under $source/blender_addon"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/addon_ui.XXXXXX") || fail "mktemp -d failed"
trap 'rm -rf "$tmp"' EXIT

# Blender's user scripts/config go to the temp folder: the test neither reads
# nor writes the user's Blender set-up.
mkdir -p "$tmp/user_scripts" "$tmp/user_config" "$tmp/work"
start=$(date +%s)
BLENDER_USER_SCRIPTS="$tmp/user_scripts" BLENDER_USER_CONFIG="$tmp/user_config" \
  "$blender" -b --factory-startup --python-exit-code 1 \
  -P "$here/addon_ui.py" -- "$clothbake" "$source" "$tmp/work" >"$tmp/blender.log" 2>&1
rc=$?
# Keep the checks and errors; drop Cycles' per-tile progress lines.
grep -v -E '^ *(Fra:|Saved:|Time:)|^$' "$tmp/blender.log"
echo "Blender exit status $rc after $(( $(date +%s) - start )) s"

[ "$rc" -eq 0 ] || fail "add-on UI checks failed (exit status $rc; see above)"
# An operator that raised instead of reporting prints a traceback, whatever it returned.
if grep -q "Traceback" "$tmp/blender.log"; then
  fail "Blender printed a Python traceback (see above)"
fi
echo "PASS: blender.addon_ui"
