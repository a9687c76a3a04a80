#!/usr/bin/env bash
# CTest blender.addon_errors: the add-on's error reports in headless Blender
# 3.4 (addon_errors.py). Fails when a check fails or when Blender printed a
# Python traceback anywhere (an operator that raised instead of reporting).
#
#   bash run_addon_errors.sh CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]
set -u

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: bash run_addon_errors.sh CLOTHBAKE_EXE SOURCE_DIR [BLENDER_EXE]" >&2
  exit 2
fi
clothbake=$1 source=$2 blender=${3:-$(command -v blender)}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -n "$blender" ] && [ -x "$blender" ] || fail "Blender executable not found"
[ -x "$clothbake" ] || fail "clothbake executable not found: $clothbake"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/addon_errors.XXXXXX") || fail "mktemp -d failed"
trap 'rm -rf "$tmp"' EXIT

mkdir -p "$tmp/user_scripts" "$tmp/user_config" "$tmp/work"
start=$(date +%s)
BLENDER_USER_SCRIPTS="$tmp/user_scripts" BLENDER_USER_CONFIG="$tmp/user_config" \
  "$blender" -b --factory-startup --python-exit-code 1 \
  -P "$here/addon_errors.py" -- "$clothbake" "$source" "$tmp/work" >"$tmp/blender.log" 2>&1
rc=$?
grep -v -E '^ *(Fra:|Saved:|Time:)|^$' "$tmp/blender.log"
echo "Blender exit status $rc after $(( $(date +%s) - start )) s"

[ "$rc" -eq 0 ] || fail "add-on error checks failed (exit status $rc; see above)"
if grep -q "Traceback" "$tmp/blender.log"; then
  fail "Blender printed a Python traceback (see above)"
fi
echo "PASS: blender.addon_errors"
