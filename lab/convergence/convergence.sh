#!/usr/bin/env bash
# Convergence of the reference renderer on a scene: renders at the scene's
# settings and at 4x and 16x the samples, and a reference with 16x the samples,
# a quarter of the step and no light roulette; prints seconds and relative
# RMSE / PSNR of each against the reference (full resolution and 2 x 2
# box-averaged).
# Usage: lab/convergence/convergence.sh [SCENE.json] [OUT_DIR]
source "$(dirname "$0")/../../scripts/lib.sh"
scene=${1:-$CLOTHBAKE_ROOT/testscenes/paper/scene.json}
out=${2:-$CLOTHBAKE_ROOT/out/convergence}
exe="$CLOTHBAKE_BUILD/baker/clothbake"
mkdir -p "$out"
spp=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1])).get('render',{}).get('spp',4))" "$scene")
step=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1])).get('render',{}).get('step_cells',0.5))" "$scene")
ref_scene="$(dirname "$scene")/.convergence_reference.json"
/usr/bin/python3 - "$scene" "$ref_scene" "$step" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.setdefault("render", {})["step_cells"] = float(sys.argv[3]) / 4
s["render"]["seed"] = 99
s["render"]["light_roulette"] = 0.0  # the plain march: independent of the default's estimator
json.dump(s, open(sys.argv[2], "w"), indent=1)
PY
trap 'rm -f "$ref_scene"' EXIT
seconds() { "$exe" render "$@" --quiet --stats | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print(round(d['setup_seconds']+d['render_seconds'],3))"; }
log "reference: $((spp * 16)) spp, step $step/4"
tref=$(seconds "$ref_scene" -o "$out/reference.exr" --spp $((spp * 16)))
echo "reference ($((spp * 16)) spp, step/4): ${tref}s"
for mult in 1 4 16; do
  n=$((spp * mult))
  t=$(seconds "$scene" -o "$out/spp$n.exr" --spp $n)
  full=$("$exe" compare "$out/reference.exr" "$out/spp$n.exr" --json)
  half=$("$exe" compare "$out/reference.exr" "$out/spp$n.exr" --json --downsample 2)
  /usr/bin/python3 - "$n" "$t" "$full" "$half" <<'PY'
import json, sys
f, h = json.loads(sys.argv[3]), json.loads(sys.argv[4])
print(f"{sys.argv[1]:>4} spp: {sys.argv[2]:>7} s   rel RMSE {100*f['relative_rmse']:.2f}%  PSNR {f['psnr']:.2f} dB"
      f"   (2x2 averaged: {100*h['relative_rmse']:.2f}%, {h['psnr']:.2f} dB)")
PY
done
