#!/usr/bin/env bash
# A WIF draft in the panel, in Blender's real window under Xvfb
# (ui_wif_panel.py: the drawdown drawn, a palette colour edited, the export
# and `clothbake volume` of it checked, a JSON spec naming the WIF):
#   ui_wif_panel.sh BLENDER CLOTHBAKE SOURCE_DIR [SCREENSHOT_DIR [WIF]]
# WIF: default testscenes/wif/real/hw_55116.wif (Handweaving.net, 214 x 214, stripes
# in 8 colours), else the first of testscenes/wif/real/*.wif, else of testscenes/wif/*.wif.
# Screenshots of the Properties editor go to SCREENSHOT_DIR (default: a temp folder).
set -euo pipefail
blender=$1 exe=$2 src=$3
tmp=$(mktemp -d)
out=${4:-$tmp/shots}
wif=${5:-}
if [[ -z $wif && -f $src/testscenes/wif/real/hw_55116.wif ]]; then
  wif=$src/testscenes/wif/real/hw_55116.wif
fi
if [[ -z $wif ]]; then
  wif=$(ls "$src"/testscenes/wif/real/*.wif 2>/dev/null | sort | head -1 || true)
  [[ -n $wif ]] || wif=$(ls "$src"/testscenes/wif/*.wif 2>/dev/null | sort | head -1 || true)
fi
[[ -n $wif && -f $wif ]] || { echo "FAIL: no WIF file under $src/testscenes/wif"; exit 1; }
xvfb_pid=
cleanup() { [[ -n $xvfb_pid ]] && kill "$xvfb_pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
source "$src/scripts/xvfb.sh"
start_xvfb "$tmp" || exit 1
mkdir -p "$tmp/user/config" "$tmp/work"
start=$(date +%s)
echo "WIF: $wif"
DISPLAY=$display BLENDER_USER_SCRIPTS=$tmp/user BLENDER_USER_CONFIG=$tmp/user/config \
  timeout 600 "$blender" --factory-startup -P "$src/tests/blender/ui_wif_panel.py" \
  -- "$exe" "$src" "$tmp/work" "$out" "$wif" >"$tmp/blender.log" 2>&1 || true
grep -E '^(ok|FAIL|     )|Traceback|Error' "$tmp/blender.log" || true
echo "Blender ran $(( $(date +%s) - start )) s; screenshots in $out: $(ls "$out" 2>/dev/null | tr '\n' ' ')"
result=$(cat "$tmp/work/ui_result.txt" 2>/dev/null || echo "no result (Blender did not reach the end)")
if [[ $result != passed ]] || grep -q Traceback "$tmp/blender.log"; then
  tail -30 "$tmp/blender.log"; echo "FAIL: $result"; exit 1
fi
echo "PASS: blender.ui_wif_panel"
