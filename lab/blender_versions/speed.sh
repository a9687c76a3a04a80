#!/usr/bin/env bash
# The cloth material in each Blender the add-on is tested on, one run on one
# machine: Apply material's seconds and Cycles' seconds per sample of the
# paper scene, on the host's Blender and in each Debian root.
#   lab/blender_versions/speed.sh MATERIAL_DIR [SAMPLES] [OUT_TSV]
# MATERIAL_DIR: a material of the paper cloth (clothbake material
# testscenes/paper/scene.json -o DIR). Each Blender renders twice (the first
# run warms the caches); the second run's figures are kept.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
material=$(realpath "$1")
samples=${2:-16}
out=${3:-/dev/stdout}
cd "$root"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { # run PLACE BLENDER_CMD...
  local place=$1
  shift
  for i in 1 2; do
    "$@" -b --factory-startup --python-exit-code 1 -P blender_addon/headless_render.py -- \
      testscenes/paper/scene.json "$material" "$tmp/$place.exr" --samples "$samples" --threads 2 \
      --timings "$tmp/$place.json" >"$tmp/$place.log" 2>&1
  done
  /usr/bin/python3 - "$tmp/$place.json" "$place" "$samples" "$("$@" --version 2>/dev/null | head -1)" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
samples = int(sys.argv[3])
print(f"{sys.argv[4]}\t{sys.argv[2]}\t{t['apply_seconds']:.2f}\t{t['render_seconds']:.2f}\t"
      f"{t['render_seconds'] / samples:.3f}")
PY
}
{
  printf "blender\twhere\tapply material (s)\tCycles render (s)\tCycles s per sample\n"
  run host blender
  for s in trixie sid; do
    CLOTHBAKE_ROOT_BUILD=0 run "$s" scripts/debian-root.sh "$s" run blender
  done
} >"$out"
