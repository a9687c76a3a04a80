#!/usr/bin/env bash
# CTest blender.addon_install: scripts/package-addon.sh builds the add-on zip
# (checked: the clothbake/ folder, no __pycache__, same bytes twice), and
# headless Blender installs it through Preferences > Add-ons > Install
# into a temporary BLENDER_USER_SCRIPTS and enables it; from 4.2 the
# extension too, built and validated by that Blender (addon_install.py).
#
#   bash run_addon_install.sh SOURCE_DIR [BLENDER_EXE]
set -u

if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: bash run_addon_install.sh SOURCE_DIR [BLENDER_EXE]" >&2
  exit 2
fi
source=$1 blender=${2:-$(command -v blender)}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -n "$blender" ] && [ -x "$blender" ] || fail "Blender executable not found"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/addon_install.XXXXXX") || fail "mktemp -d failed"
trap 'rm -rf "$tmp"' EXIT

# Byte-code caches in the sources (any Blender or pytest run leaves them)
# must not reach the zip.
bash "$source/scripts/package-addon.sh" -o "$tmp/a.zip" || fail "package-addon.sh failed"
bash "$source/scripts/package-addon.sh" -o "$tmp/b.zip" || fail "package-addon.sh failed"
cmp -s "$tmp/a.zip" "$tmp/b.zip" || fail "the zip differs between two runs"
/usr/bin/python3 - "$tmp/a.zip" <<'PY' || fail "zip contents"
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
assert "clothbake/__init__.py" in names, names
assert all(n.startswith("clothbake/") for n in names), names
assert not any("__pycache__" in n or n.endswith(".pyc") for n in names), names
print(f"zip: {len(names)} files under clothbake/")
PY

extension=()
version=$("$blender" --version 2>/dev/null | sed -n 's/^Blender \([0-9][0-9.]*\).*/\1/p' | head -1)
if [[ $(printf '%s\n4.2\n' "$version" | sort -V | head -1) == 4.2 ]]; then
  bash "$source/scripts/package-addon.sh" -o "$tmp/c.zip" --extension "$tmp/ext" --blender "$blender" ||
    fail "package-addon.sh --extension failed"
  extension=("$(ls "$tmp"/ext/clothbake-*.zip)")
fi

mkdir -p "$tmp/user_scripts" "$tmp/user_config" "$tmp/user_extensions"
BLENDER_USER_SCRIPTS="$tmp/user_scripts" BLENDER_USER_CONFIG="$tmp/user_config" \
  BLENDER_USER_EXTENSIONS="$tmp/user_extensions" \
  "$blender" -b --factory-startup --python-exit-code 1 \
  -P "$here/addon_install.py" -- "$tmp/a.zip" "$tmp/user_scripts" "${extension[@]}" >"$tmp/blender.log" 2>&1
rc=$?
grep -v -E '^$' "$tmp/blender.log"
[ "$rc" -eq 0 ] || fail "add-on install checks failed (exit status $rc; see above)"
echo "PASS: blender.addon_install"
