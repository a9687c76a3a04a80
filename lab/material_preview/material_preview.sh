#!/usr/bin/env bash
# Material Preview of the cloth material, measured (material_preview.py):
#   lab/material_preview/material_preview.sh CLOTHBAKE SCENE.json MATERIAL_DIR OUT_DIR [SAMPLES]
# In Blender's real window under Xvfb: Eevee's F12 and the viewport's
# Material Preview (Viewport Render Image, through the camera) of the scene
# with the material applied (exact route), SAMPLES samples each (default
# 64); then `clothbake lookup-render` of the same scene and material at 64
# spp. Prints each one's relative RMSE (OIIO's RMS difference over the
# reference's mean) and mean against the others, into OUT_DIR/figures.txt
# too, and writes PNGs of the three. About 2 minutes on the paper scene.
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: material_preview.sh CLOTHBAKE SCENE.json MATERIAL_DIR OUT_DIR [SAMPLES]" >&2; exit 2; }
exe=$(realpath "$1") scene=$(realpath "$2") material=$(realpath "$3") out=$4 samples=${5:-64}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mkdir -p "$out"; out=$(realpath "$out")
tmp=$(mktemp -d)
xvfb_pid=
cleanup() { [[ -n $xvfb_pid ]] && kill "$xvfb_pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
source "$root/scripts/xvfb.sh"
start_xvfb "$tmp" 140 || exit 1
mkdir -p "$tmp/user/config"
rm -f "$out/result.txt"
DISPLAY=$display BLENDER_USER_SCRIPTS=$tmp/user BLENDER_USER_CONFIG=$tmp/user/config \
  timeout 900 blender --factory-startup -P "$root/lab/material_preview/material_preview.py" \
  -- "$root/blender_addon" "$scene" "$material" "$out" "$samples" >"$out/blender.log" 2>&1 || true
grep -E "^(step|notes|eevee|viewport)|Traceback|Error" "$out/blender.log" || true
[[ $(cat "$out/result.txt" 2>/dev/null) == passed ]] || { echo "material_preview.sh: Blender did not finish (see $out/blender.log)" >&2; exit 1; }
"$exe" lookup-render "$scene" "$material" -o "$out/lookup.exr" --spp 64 --quiet
/usr/bin/python3 - "$out" <<'EOF' | tee "$out/figures.txt"
import sys
import OpenImageIO as oiio
out = sys.argv[1]
imgs = {k: oiio.ImageBuf(f"{out}/{k}.exr") for k in ("lookup", "eevee", "preview")}
rgb = {k: oiio.ImageBufAlgo.channels(b, (0, 1, 2)) for k, b in imgs.items()}
def mean(b):
    return sum(oiio.ImageBufAlgo.computePixelStats(b).avg) / 3
for k, b in rgb.items():
    oiio.ImageBufAlgo.pow(b, (1 / 2.2,) * 3).write(f"{out}/{k}.png", "uint8")
for test, ref in (("eevee", "lookup"), ("preview", "lookup"), ("preview", "eevee")):
    c = oiio.ImageBufAlgo.compare(rgb[test], rgb[ref], 1e9, 1e9)
    print(f"{test} against {ref}: relative RMSE {100 * c.rms_error / mean(rgb[ref]):.2f} %, "
          f"mean {mean(rgb[test]):.4f} against {mean(rgb[ref]):.4f}")
EOF
