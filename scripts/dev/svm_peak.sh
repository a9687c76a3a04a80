#!/usr/bin/env bash
# The cloth material's SVM stack in Cycles (docs/design/material.md, "Lights and
# the SVM stack"): renders SCENE.json from MATERIAL_DIR through the headless
# route at 1 sample with Cycles' debug log, and prints per cloth shader its
# SVM node count and peak stack use (Cycles' limit is 255 floats; past it
# Cycles prints "out of SVM stack space" and the shader renders black).
#   scripts/dev/svm_peak.sh SCENE.json MATERIAL_DIR [exact|cycles-lit] [ADDON_DIR]
# ADDON_DIR (default: this checkout's blender_addon) lets one measure a
# scratch copy of the add-on against the checkout's.
set -euo pipefail
[ $# -ge 2 ] && [ $# -le 4 ] || {
  echo "usage: scripts/dev/svm_peak.sh SCENE.json MATERIAL_DIR [exact|cycles-lit] [ADDON_DIR]" >&2
  exit 2; }
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=$1 material=$2 route=${3:-exact} addon=${4:-$root/blender_addon}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/svm_peak.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# Blender 5.x logs Cycles' summary at trace level only, each line behind a
# "time  cycles  |" margin.
log_level=()
major=$(blender --version 2>/dev/null | awk '/^Blender/ {split($2, v, "."); print v[1]; exit}')
((${major:-3} >= 5)) && log_level=(--log-level trace)
blender -b --factory-startup --debug-cycles --verbose 4 "${log_level[@]}" --python-exit-code 1 \
  -P "$addon/headless_render.py" -- "$scene" "$material" "$tmp/out.exr" \
  --samples 1 --threads 1 --route "$route" >"$tmp/log" 2>&1 || {
  tail -20 "$tmp/log" >&2; echo "svm_peak.sh: the render failed" >&2; exit 1; }
if grep -q "out of SVM stack space" "$tmp/log"; then
  grep "out of SVM stack space" "$tmp/log" | sort -u
  status=overflow
else
  status=ok
fi
# Cycles' compilation summary: "Shader name:", "Number of SVM nodes:",
# "Peak stack usage:" lines in that order; print the clothbake ones.
sed -E 's/^[0-9:. ]*(cycles +)?\| ?//' "$tmp/log" | awk -v route="$route" '
  /^Shader name:/ { name = substr($0, 14) }
  /^Number of SVM nodes:/ { nodes = $NF }
  /^Peak stack usage:/ { if (name ~ /clothbake/) printf "%s\t%s\tnodes %s\tpeak %s of 255\n", route, name, nodes, $NF }
' | sort -u
echo "$route: $status"
[ "$status" = ok ]
