#!/usr/bin/env bash
# CTest blender.vdb_loads: bake the volume with clothbake, then check inside
# Blender 3.4 (vdb_load.py) that the VDB loads with the expected grids, voxel
# counts and extents, and that Cycles renders its voxels.
#
#   bash run_vdb_load.sh BLENDER_EXE CLOTHBAKE_EXE SPEC_JSON
#
# Exit status 0 when every check passes, non-zero otherwise.
set -u

if [ $# -ne 3 ]; then
  echo "usage: bash run_vdb_load.sh BLENDER_EXE CLOTHBAKE_EXE SPEC_JSON" >&2
  exit 2
fi
blender=$1 clothbake=$2 spec=$3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -x "$blender" ] || fail "Blender executable not found: $blender"
[ -x "$clothbake" ] || fail "clothbake executable not found: $clothbake"
[ -f "$spec" ] || fail "spec not found: $spec"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/vdb_load.XXXXXX") || fail "mktemp -d failed"
trap 'rm -rf "$tmp"' EXIT

if ! "$clothbake" volume "$spec" -o "$tmp/vol" >"$tmp/clothbake.log" 2>&1; then
  cat "$tmp/clothbake.log" >&2
  fail "clothbake volume $spec -o $tmp/vol failed"
fi
for f in volume.vdb volume.json; do
  [ -s "$tmp/vol/$f" ] || fail "clothbake volume wrote no $f"
done

# Blender's user scripts/config go to the temp folder: the test neither reads
# nor writes the user's Blender set-up.
mkdir -p "$tmp/user_scripts" "$tmp/user_config"
start=$(date +%s)
BLENDER_USER_SCRIPTS="$tmp/user_scripts" BLENDER_USER_CONFIG="$tmp/user_config" \
  "$blender" -b --factory-startup --python-exit-code 1 \
  -P "$here/vdb_load.py" -- "$tmp/vol/volume.vdb" "$tmp/vol/volume.json" "$tmp/render.exr" \
  >"$tmp/blender.log" 2>&1
rc=$?
# Keep the checks and errors; drop Cycles' per-tile progress lines.
grep -v -E '^ *(Fra:|Saved:|Time:)|^$' "$tmp/blender.log"
echo "Blender exit status $rc after $(( $(date +%s) - start )) s"

[ "$rc" -eq 0 ] || fail "Blender VDB load/render checks failed (exit status $rc; see above)"
echo "PASS: blender.vdb_loads"
