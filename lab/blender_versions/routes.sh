#!/usr/bin/env bash
# The paper scene's material through the headless route in each Blender, against
# lookup-render of the same material: Cycles exact, Cycles cycles-lit and Eevee.
#   lab/blender_versions/routes.sh MATERIAL_DIR [SAMPLES] [OUT_TSV]
# Relative RMSE per pixel (clothbake compare) and the mean's ratio. The
# figures of one Blender against another show what the version changes; the
# lookup-render reference is rendered once, at 4 x SAMPLES.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
material=$(realpath "$1")
samples=${2:-64}
out=${3:-/dev/stdout}
cd "$root"
cb=build/baker/clothbake
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene=testscenes/paper/scene.json
"$cb" lookup-render "$scene" "$material" -o "$tmp/ref.exr" --spp $((4 * samples)) --quiet
row() { # row PLACE ENGINE ROUTE BLENDER_CMD...
  local place=$1 engine=$2 route=$3
  shift 3
  "$@" -b --factory-startup --python-exit-code 1 -P blender_addon/headless_render.py -- \
    "$scene" "$material" "$tmp/b.exr" --samples "$samples" --threads 2 --engine "$engine" \
    --route "$route" >"$tmp/log" 2>&1 || { echo -e "$place\t$engine\t$route\tfailed"; return; }
  "$cb" compare "$tmp/ref.exr" "$tmp/b.exr" --json >"$tmp/c.json"
  /usr/bin/python3 - "$tmp/c.json" "$tmp/ref.exr" "$tmp/b.exr" "$place" "$engine" "$route" \
    "$("$@" --version 2>/dev/null | head -1)" <<'PY'
import json, sys
import OpenImageIO as oiio
c = json.load(open(sys.argv[1]))
ref = oiio.ImageBuf(sys.argv[2]).get_pixels(oiio.FLOAT)[..., :3].mean()
got = oiio.ImageBuf(sys.argv[3]).get_pixels(oiio.FLOAT)[..., :3].mean()
print(f"{sys.argv[7]}\t{sys.argv[5]}\t{sys.argv[6]}\t{100 * c['relative_rmse']:.2f} %\t{got / ref:.4f}")
PY
}
{
  printf "blender\tengine\troute\trelative RMSE against lookup-render\tmean ratio\n"
  for r in "cycles exact" "cycles cycles-lit" "eevee exact"; do
    read -r engine route <<<"$r"
    row host "$engine" "$route" blender
    for s in trixie sid; do
      CLOTHBAKE_ROOT_BUILD=0 row "$s" "$engine" "$route" scripts/debian-root.sh "$s" run blender
    done
  done
} >"$out"
