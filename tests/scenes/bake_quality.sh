#!/usr/bin/env bash
# The baked lookup against the reference renderer on a scene: an adaptive bake
# (the scene's camera), rendered through the lookup with the add-on's
# interpolation, must be as close to the render (seed 1) as a second render
# with another seed (seed 2) is: PSNR(lookup, render1) >= PSNR(render2, render1),
# over RGB with the render's maximum as the peak. The bound is measured, not
# assumed: it is the render's own sampling noise at the scene's settings.
#   bake_quality.sh EXE SCENE [--fixed-bound DB] BAKE_ARGS...
# With --fixed-bound the bound is DB instead (a stated figure held against
# regressions; the bake and the render are deterministic, so the figure is too).
set -eu
exe=$1 scene=$2
shift 2
fixed=""
if [[ ${1:-} == --fixed-bound ]]; then
  fixed=$2
  shift 2
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The seed-2 scene goes into the temporary folder, its files named by
# absolute paths (it used to be written beside the scene, into the source tree).
sed 's/"seed": *[0-9]*/"seed": 2/' "$scene" | /usr/bin/python3 -c '
import json, os, sys
folder = os.path.dirname(os.path.abspath(sys.argv[1]))
scene = json.load(sys.stdin)
for o in scene["objects"]:
    for key in ("mesh", "cloth", "volume"):
        if isinstance(o.get(key), str):
            o[key] = os.path.join(folder, o[key])
json.dump(scene, sys.stdout)' "$scene" >"$tmp/seed2.json"
"$exe" render "$scene" -o "$tmp/render1.exr" --quiet
[[ -n $fixed ]] || "$exe" render "$tmp/seed2.json" -o "$tmp/render2.exr" --quiet
"$exe" bake "$scene" -o "$tmp/bake" --quiet "$@" >"$tmp/bake.json"
"$exe" lookup-render "$scene" "$tmp/bake" -o "$tmp/lookup.exr" --quiet
if [[ -n $fixed ]]; then
  noise=$fixed
else
  noise=$("$exe" compare "$tmp/render1.exr" "$tmp/render2.exr" --json | /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin)['psnr'])")
fi
bake=$("$exe" compare "$tmp/render1.exr" "$tmp/lookup.exr" --json | /usr/bin/python3 -c "import json,sys; print(json.load(sys.stdin)['psnr'])")
echo "PSNR lookup-render vs render: $bake dB; bound ${fixed:+(fixed) }$noise dB"
/usr/bin/python3 -c "import sys; sys.exit(0 if float('$bake') >= float('$noise') else 1)"
