#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the bundled paper
# scene, writing out/paper/:
#   volume.vdb + previews    the cloth's volume texture (clothbake volume)
#   fiber_lobe.png           the fibre model's lobe
#   reference.exr/.png       clothbake's reference ray-marcher
#   bake/                    an adaptive bake for the scene's camera
#   lookup.exr/.png          the scene drawn from the bake by clothbake itself
#   blender.exr/.png         the scene drawn from the bake by Blender Cycles (the add-on)
#   compare.png              reference | Blender | difference heatmap
#   metrics.json             PSNR and RMSE of Blender and of lookup-render against
#                            the reference, and the seconds of every step
# Settings (why: docs/design/blender-nodes.md "Figures"): the reference and both lookup
# renders at 64 samples per pixel, the bake at 3 texels per pixel, K = 16, 2 spp.
source "$(dirname "$0")/lib.sh"
install_packages
build_all
exe="$CLOTHBAKE_BUILD/baker/clothbake"
out="$CLOTHBAKE_ROOT/out/paper"
scene="$CLOTHBAKE_ROOT/testscenes/paper/scene.json"
mkdir -p "$out"
timings="$out/.timings.$$"
: >"$timings"
trap 'rm -f "$timings"' EXIT
# step NAME COMMAND...: runs a step and records its wall seconds.
step() {
  local name=$1 t0 t1
  shift
  t0=$(date +%s.%N)
  "$@"
  t1=$(date +%s.%N)
  echo "$name $t0 $t1" >>"$timings"
}

log "generating the paper cloth's volume texture into $out"
step volume "$exe" volume "$CLOTHBAKE_ROOT/testscenes/paper/cloth.json" -o "$out"
log "fibre lobe of the paper's fibre (aspect 8) lit from 45 degrees"
"$exe" fiber --aspect 8 --tangent 1,0,0 --light 0,0.7071,0.7071 \
  --view 0,0,1 --samples 256 --plot "$out/fiber_lobe.png" >"$out/fiber.json"
log "reference render of the paper scene (64 spp)"
step reference "$exe" render "$scene" -o "$out/reference.exr" --png "$out/reference.png" --spp 64
log "adaptive bake for the scene's camera"
step bake "$exe" bake "$scene" -o "$out/bake" --adaptive --directions 16 --texels-per-pixel 3 \
  --spp 2 >"$out/bake.json"
log "the scene rendered from the bake by clothbake (lookup-render, 64 spp)"
step lookup_render "$exe" lookup-render "$scene" "$out/bake" -o "$out/lookup.exr" \
  --png "$out/lookup.png" --spp 64
log "the scene rendered from the bake by Blender Cycles with the add-on (64 samples)"
blender_user=$(mktemp -d)
trap 'rm -f "$timings"; rm -rf "$blender_user"' EXIT
BLENDER_USER_SCRIPTS=$blender_user BLENDER_USER_CONFIG=$blender_user/config \
  step blender blender -b --factory-startup --python-exit-code 1 \
  -P "$CLOTHBAKE_ROOT/blender_addon/headless_render.py" -- "$scene" "$out/bake" \
  "$out/blender.exr" --samples 64 --png "$out/blender.png" --timings "$out/blender_timings.json" \
  >"$out/blender.log" 2>&1 || { cat "$out/blender.log" >&2; exit 1; }
log "comparing with the reference"
step compare "$exe" compare "$out/reference.exr" "$out/blender.exr" --sheet "$out/compare.png" \
  --heatmap "$out/heatmap.png" --json >"$out/compare_blender.json"
"$exe" compare "$out/reference.exr" "$out/lookup.exr" --json >"$out/compare_lookup.json"
/usr/bin/python3 - "$out" "$timings" <<'PY'
import json, os, sys
out, timings = sys.argv[1], sys.argv[2]
seconds = {}
for line in open(timings):
    name, t0, t1 = line.split()
    seconds[name] = round(float(t1) - float(t0), 3)
blender = json.load(open(os.path.join(out, "compare_blender.json")))
lookup = json.load(open(os.path.join(out, "compare_lookup.json")))
inside = json.load(open(os.path.join(out, "blender_timings.json")))
bake = json.load(open(os.path.join(out, "bake.json")))
metrics = {
    "scene": "testscenes/paper/scene.json",
    "psnr": blender["psnr"], "rmse": blender["rmse"],
    "relative_rmse": blender["relative_rmse"], "max_error": blender["max_error"],
    "lookup_render": {"psnr": lookup["psnr"], "rmse": lookup["rmse"]},
    "seconds": seconds,
    "blender_seconds": {k: round(v, 3) for k, v in inside.items() if k.endswith("_seconds")},
    "settings": {"reference_spp": 64, "lookup_render_spp": 64, "blender_samples": 64,
                 "bake": "--adaptive --directions 16 --texels-per-pixel 3 --spp 2"},
    "bake": {k: bake[k] for k in ("bake_seconds", "direction_tiles", "texels", "bytes_on_disk",
                                  "march_samples") if k in bake},
    "peak": "reference maximum over RGB",
}
tmp = os.path.join(out, "metrics.json.tmp")
with open(tmp, "w") as f:
    json.dump(metrics, f, indent=2)
    f.write("\n")
os.replace(tmp, os.path.join(out, "metrics.json"))
print(json.dumps(metrics, indent=2))
PY
log "done: Blender vs reference PSNR $(/usr/bin/python3 -c "import json; print(round(json.load(open('$out/metrics.json'))['psnr'], 2))") dB; files: $(cd "$out" && ls | tr '\n' ' ')"
