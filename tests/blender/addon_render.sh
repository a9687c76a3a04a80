#!/usr/bin/env bash
# The add-on against clothbake's own lookup reader, headless in Blender:
# register the add-on, import the paper scene, apply an adaptive bake of it,
# render with Cycles at 16 samples, and compare with `clothbake lookup-render`
# of the same bake at 16 samples.
#   addon_render.sh BLENDER CLOTHBAKE SOURCE_DIR
#
# Threshold, from the samples used: both images are 16-sample Monte Carlo
# estimates of the same pixel integrals (box filter over the pixel, the
# lookup read with the same interpolation), so if Blender reads the lookup
# correctly its difference from lookup-render (seed 1) is sampling noise of
# the same size as that between two lookup-renders with different seeds:
#     PSNR(blender, lookup1) >= PSNR(lookup2, lookup1) - 0.5 dB.
# The 0.5 dB covers the outline, where Blender's two triangles per quad and
# clothbake's bilinear patch cover slightly different pixels; the PSNR of
# 113,000 pixels scatters by ~0.05 dB from seed to seed. Measured on this
# machine: 45.3 dB against a bound of 45.1 - 0.5 dB (K = 16 bake); reading
# (s, t) from Blender's triangles instead of the patch gave 35.4 dB.
set -euo pipefail
blender=$1 exe=$2 src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export BLENDER_USER_SCRIPTS=$tmp/user BLENDER_USER_CONFIG=$tmp/user/config
scene=$src/testscenes/paper/scene.json

"$exe" bake "$scene" -o "$tmp/bake" --adaptive --directions 8 --spp 1 --quiet >/dev/null
"$exe" lookup-render "$scene" "$tmp/bake" -o "$tmp/lookup1.exr" --spp 16 --seed 1 --quiet
"$exe" lookup-render "$scene" "$tmp/bake" -o "$tmp/lookup2.exr" --spp 16 --seed 2 --quiet
"$blender" -b --factory-startup --python-exit-code 1 -P "$src/blender_addon/headless_render.py" \
  -- "$scene" "$tmp/bake" "$tmp/blender.exr" --samples 16 --timings "$tmp/timings.json" \
  >"$tmp/blender.log" 2>&1 || { cat "$tmp/blender.log"; exit 1; }
[[ -f $tmp/blender.exr ]] || { echo "no blender.exr"; exit 1; }

psnr() { "$exe" compare "$1" "$2" --json | /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin)['psnr'])"; }
noise=$(psnr "$tmp/lookup1.exr" "$tmp/lookup2.exr")
blend=$(psnr "$tmp/lookup1.exr" "$tmp/blender.exr")
echo "PSNR blender vs lookup-render: $blend dB; lookup-render seed 2 vs seed 1: $noise dB (bound: $noise - 0.5)"
cat "$tmp/timings.json"
/usr/bin/python3 -c "import sys; sys.exit(0 if float('$blend') >= float('$noise') - 0.5 else 1)"
