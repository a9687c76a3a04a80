#!/usr/bin/env bash
# A real overshot draft baked from the panel at its defaults, in Blender's
# real window under Xvfb (panel_overshot.py):
#   lab/panel_overshot/panel_overshot.sh CLOTHBAKE OUT_DIR [WIF]
# WIF: default testscenes/wif/real/tw_honeysuckle.wif (TempoWeave, 91 x 480).
# Blender's default scene, the cube replaced by a plane of 64 quads made a
# cloth, the WIF loaded, the .blend saved (the material goes beside it),
# Estimate, Bake material (its confirmation dialog answered), Material
# Preview. Screenshots and blender.log in OUT_DIR. Takes as long as the bake
# (about 6 minutes on 2 cores for the overshot); CLOTHBAKE_PANEL_NO_BAKE=1
# stops at the confirmation (about a minute).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: panel_overshot.sh CLOTHBAKE OUT_DIR [WIF]" >&2; exit 2; }
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
exe=$(realpath "$1") out=$2 wif=$(realpath "${3:-$root/testscenes/wif/real/tw_honeysuckle.wif}")
mkdir -p "$out"; out=$(realpath "$out")
tmp=$(mktemp -d)
xvfb_pid=
cleanup() { [[ -n $xvfb_pid ]] && kill "$xvfb_pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
source "$root/scripts/xvfb.sh"
start_xvfb "$tmp" 150 || exit 1
mkdir -p "$tmp/user/config" "$out/work"
rm -f "$out/work/ui_result.txt"
DISPLAY=$display BLENDER_USER_SCRIPTS=$tmp/user BLENDER_USER_CONFIG=$tmp/user/config \
  timeout 3600 blender --factory-startup -P "$root/lab/panel_overshot/panel_overshot.py" \
  -- "$exe" "$root" "$out/work" "$out" "$wif" >"$out/blender.log" 2>&1 || true
grep -E '^(ok|FAIL|step|     )|Traceback|Error' "$out/blender.log" || true
[[ $(cat "$out/work/ui_result.txt" 2>/dev/null) == passed ]] ||
  { echo "panel_overshot.sh: not passed (see $out/blender.log)" >&2; exit 1; }
