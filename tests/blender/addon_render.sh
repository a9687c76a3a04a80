#!/usr/bin/env bash
# The add-on against clothbake's own lookup reader, headless in Blender:
# register the add-on, import the paper scene, apply an adaptive bake of it,
# render with Cycles at 16 samples, and compare with `clothbake lookup-render`
# of the same bake at 16 samples; then the same seen from behind the cloth
# (back faces only).
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
# Two views of the paper scene: the scene's own (front faces), and one from
# behind the cloth, where every visible face is a back face (the lookup's
# back side, which Apply must select by the patch's own normal, not
# Cycles' flipped one).
front=$src/testscenes/paper/scene.json
back=$tmp/paper_from_behind.json
/usr/bin/python3 - "$front" "$back" <<'PY'
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
scene = json.load(open(src))
folder = os.path.dirname(os.path.abspath(src))
for o in scene["objects"]:
    o["mesh"] = os.path.join(folder, o["mesh"])
    o["cloth"] = os.path.join(folder, o["cloth"])
scene["camera"]["position"] = [0.9, -0.2, -3.2]
scene["camera"]["look_at"] = [-0.1, -0.55, 0.2]
json.dump(scene, open(dst, "w"), indent=2)
PY

psnr() { "$exe" compare "$1" "$2" --json | /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin)['psnr'])"; }
status=0
for view in front back; do
  scene=${!view}
  "$exe" bake "$scene" -o "$tmp/bake_$view" --adaptive --directions 8 --spp 1 --quiet >/dev/null
  "$exe" lookup-render "$scene" "$tmp/bake_$view" -o "$tmp/lookup1_$view.exr" --spp 16 --seed 1 --quiet
  "$exe" lookup-render "$scene" "$tmp/bake_$view" -o "$tmp/lookup2_$view.exr" --spp 16 --seed 2 --quiet
  "$blender" -b --factory-startup --python-exit-code 1 -P "$src/blender_addon/headless_render.py" \
    -- "$scene" "$tmp/bake_$view" "$tmp/blender_$view.exr" --samples 16 \
    --timings "$tmp/timings_$view.json" >"$tmp/blender.log" 2>&1 || { cat "$tmp/blender.log"; exit 1; }
  [[ -f $tmp/blender_$view.exr ]] || { echo "no blender_$view.exr"; exit 1; }
  noise=$(psnr "$tmp/lookup1_$view.exr" "$tmp/lookup2_$view.exr")
  blend=$(psnr "$tmp/lookup1_$view.exr" "$tmp/blender_$view.exr")
  # The back view must actually show the back side: its bake holds back nodes.
  back_nodes=$(/usr/bin/python3 -c "import json; m = json.load(open('$tmp/bake_$view/manifest.json')); k = m['direction_map']['k']; print(sum(f[k*k:].count('1') for f in m['objects'][0]['baked']))")
  echo "$view view: PSNR blender vs lookup-render $blend dB; lookup-render seed 2 vs seed 1 $noise dB (bound: $noise - 0.5); back-side squares baked: $back_nodes"
  cat "$tmp/timings_$view.json"
  /usr/bin/python3 -c "import sys; sys.exit(0 if float('$blend') >= float('$noise') - 0.5 else 1)" || status=1
  if [[ $view == back ]] && ((back_nodes == 0)); then echo "the back view baked no back-side node"; status=1; fi
done
exit $status
