#!/usr/bin/env bash
# Regenerates the small stored reference images of the test scenes: a 64-spp
# render (16x the scenes' default 4), seed 7 (the tests render with the scenes'
# own seed, so reference and test noise are independent), box-averaged 2 x 2,
# stored as half-float EXR. Run after a deliberate change of the renderer's
# output, and say why in the commit.
source "$(dirname "$0")/../lib.sh"
exe="$CLOTHBAKE_BUILD/baker/clothbake"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in paper slab; do
  dir="$CLOTHBAKE_ROOT/testscenes/$scene"
  sed 's/"seed": *[0-9]*/"seed": 7/' "$dir/scene.json" >"$dir/.reference_scene.json"
  "$exe" render "$dir/.reference_scene.json" -o "$tmp/full.exr" --spp 64 --quiet
  rm "$dir/.reference_scene.json"
  oiiotool "$tmp/full.exr" --resize:filter=box "50%" -d half --compression zip -o "$dir/reference.exr"
  log "$scene: $(oiiotool --info "$dir/reference.exr" | head -1)"
done
