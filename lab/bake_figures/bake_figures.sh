#!/usr/bin/env bash
# Bake time, size and accuracy on a scene: the reference render, an adaptive
# bake and full bakes at K = 4, 8, 16; each lookup-rendered and compared with
# the render at the scene's samples. Prints a Markdown table.
# Usage: lab/bake_figures/bake_figures.sh [SCENE.json] [OUT_DIR] [FULL_TEXELS] [FULL_SPP]
source "$(dirname "$0")/../../scripts/lib.sh"
scene=${1:-$CLOTHBAKE_ROOT/testscenes/paper/scene.json}
out=${2:-$CLOTHBAKE_ROOT/out/bake_figures}
full_texels=${3:-32}
full_spp=${4:-1}
exe="$CLOTHBAKE_BUILD/baker/clothbake"
mkdir -p "$out"
t0=$(date +%s.%N)
"$exe" render "$scene" -o "$out/render.exr" --quiet
t1=$(date +%s.%N)
echo "| bake | K | texels | sub-texel spp | direction tiles | bake seconds | bytes on disk | lookup-render vs render (PSNR, rel. RMSE) |"
echo "|---|---|---|---|---|---|---|---|"
echo "| (reference render) | | | | | $(/usr/bin/python3 -c "print(f'{$t1 - $t0:.2f}')") | | |"
row() {  # name, bake args...
  local name=$1; shift
  "$exe" bake "$scene" -o "$out/$name" --quiet "$@" >"$out/$name.json"
  "$exe" lookup-render "$scene" "$out/$name" -o "$out/$name.exr" --quiet
  "$exe" compare "$out/render.exr" "$out/$name.exr" --json >"$out/$name.compare.json"
  /usr/bin/python3 - "$name" "$out/$name.json" "$out/$name.compare.json" "$out/$name/manifest.json" <<'PY'
import json, sys
b, c, m = (json.load(open(p)) for p in sys.argv[2:5])
s = m["settings"]
texels = "adaptive" if s["adaptive"] else s["texels"]
print(f"| {sys.argv[1]} | {m['direction_map']['k']} | {texels} | {s['spp']} | {b['direction_tiles']} of {b['full_direction_tiles']} "
      f"| {b['bake_seconds']:.1f} | {b['bytes_on_disk']/2**20:.1f} MiB | {c['psnr']:.2f} dB, {100*c['relative_rmse']:.1f}% |")
PY
}
row adaptive_k16 --adaptive --directions 16
row adaptive_k8 --adaptive --directions 8
for k in 4 8 16; do row full_k$k --directions $k --texels "$full_texels" --spp "$full_spp"; done
