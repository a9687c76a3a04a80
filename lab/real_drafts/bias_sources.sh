#!/bin/bash
# Where a real draft's material loses its brightness against the reference:
# one knob at a time on a draft real_drafts.py has measured, then the same
# cloth on a flat plane seen obliquely and head-on.
#
#   lab/real_drafts/bias_sources.sh CLOTHBAKE WORK/NAME [--flat-only]
#
# WORK/NAME holds real_drafts.py's scene.json, ref_seed1.exr, ref_seed1.json,
# lookup.exr and material/. Writes variants beside them (bias/) and prints
# each image's cloth mean over the reference's and its errors (means.py);
# on the plane, the seed floor too (the reference with generator seed 2).
# About 25 minutes on 2 cores for d2w_zeros, 6 with --flat-only.
set -euo pipefail
exe=$(realpath "$1")
d=$(realpath "$2")
flat_only=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out="$d/bias"
mkdir -p "$out"
py=/usr/bin/python3

# A copy of a scene JSON with fields of "render" or the first object set:
# edit IN OUT 'render.step_cells=0.125' 'camera={...}' ...
edit() {
  "$py" - "$@" <<'EOF'
import json, sys
src, dst, *sets = sys.argv[1:]
s = json.load(open(src))
for kv in sets:
    key, value = kv.split("=", 1)
    if "." not in key:
        s[key] = json.loads(value)
        continue
    where, field = key.split(".", 1)
    node = s["objects"][0] if where == "object" else s.setdefault(where, {})
    node[field] = json.loads(value)
json.dump(s, open(dst, "w"), indent=1)
EOF
}

bake() {  # bake NAME SCENE [material flags...]
  local name=$1 scene=$2
  shift 2
  [ -f "$out/lookup_$name.exr" ] && return
  "$exe" material "$scene" -o "$out/material_$name" --quiet "$@" >/dev/null
  "$exe" lookup-render "$d/scene.json" "$out/material_$name" -o "$out/lookup_$name.exr" \
    --spp 64 --quiet
  rm -rf "$out/material_$name"
}

if [ "$flat_only" != --flat-only ]; then
echo "== the paper scene's folds: one knob at a time (reference: quarter step, seed 1)"
edit "$d/scene.json" "$out/scene_quarter_step.json" 'render.step_cells=0.125'
edit "$d/scene.json" "$out/scene_no_roulette.json" 'render.light_roulette=0.0'
bake quarter_step "$out/scene_quarter_step.json"
bake no_roulette "$out/scene_no_roulette.json"
bake rgb "$d/scene.json" --parts rgb
bake full_rank "$d/scene.json" --max-error 0
bake exact_tangents "$d/scene.json" --fiber-tangent-nodes 0
bake fields_x4 "$d/scene.json" --light-fields interpolated --field-supersample 4
bake square_light_map "$d/scene.json" --light-map square
bake views_8 "$d/scene.json" --directions 8
[ -f "$out/lookup_bilinear.exr" ] ||
  "$exe" lookup-render "$d/scene.json" "$d/material" -o "$out/lookup_bilinear.exr" --spp 64 \
    --quiet --light-filter bilinear
edit "$d/ref_seed1.json" "$out/ref_half_step.json" 'render.step_cells=0.5'
[ -f "$out/ref_half_step.exr" ] ||
  "$exe" render "$out/ref_half_step.json" -o "$out/ref_half_step.exr" --spp 64 --quiet
"$py" "$here/means.py" "$d/ref_seed1.exr" "$d/lookup.exr" "$out"/lookup_*.exr \
  "$out/ref_half_step.exr"
fi

echo "== the same cloth on a flat plane (testscenes/flat's mesh), the paper scene's lights"
flat_camera='{"position": [1.39, -2.981, 1.464], "look_at": [0.0, -0.05, 0.0], "up": [0, 0, 1], "fov_deg": 44, "fov_axis": "horizontal", "resolution": [320, 200]}'
head_on='{"position": [0.3, -0.5, 3.2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 44, "fov_axis": "horizontal", "resolution": [320, 200]}'
mesh="\"$root/testscenes/flat/cloth.obj\""
edit "$d/scene.json" "$out/flat.json" "object.mesh=$mesh" "camera=$flat_camera"
[ -d "$out/material_flat" ] || "$exe" material "$out/flat.json" -o "$out/material_flat" --quiet >/dev/null
for view in oblique head_on; do
  camera=$flat_camera
  [ $view = head_on ] && camera=$head_on
  edit "$out/flat.json" "$out/flat_$view.json" "camera=$camera"
  for step in 0.125 0.5; do
    edit "$out/flat_$view.json" "$out/flat_${view}_ref_$step.json" "render.step_cells=$step" \
      'render.light_roulette=0.0' 'render.seed=7'
    [ -f "$out/flat_${view}_ref_$step.exr" ] ||
      "$exe" render "$out/flat_${view}_ref_$step.json" -o "$out/flat_${view}_ref_$step.exr" \
        --spp 64 --quiet
  done
  seed2="\"$d/cloth_seed2.json\""
  edit "$out/flat_${view}_ref_0.125.json" "$out/flat_${view}_ref_seed2.json" "object.cloth=$seed2"
  [ -f "$out/flat_${view}_ref_seed2.exr" ] ||
    "$exe" render "$out/flat_${view}_ref_seed2.json" -o "$out/flat_${view}_ref_seed2.exr" \
      --spp 64 --quiet
  [ -f "$out/flat_${view}_lookup.exr" ] ||
    "$exe" lookup-render "$out/flat_$view.json" "$out/material_flat" \
      -o "$out/flat_${view}_lookup.exr" --spp 64 --quiet
  echo "-- $view, against the reference at a quarter step"
  "$py" "$here/means.py" "$out/flat_${view}_ref_0.125.exr" "$out/flat_${view}_ref_0.5.exr" \
    "$out/flat_${view}_lookup.exr" "$out/flat_${view}_ref_seed2.exr"
done
