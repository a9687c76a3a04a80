#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the bundled paper
# scene, writing out/paper/: the cloth's volume texture (VDB + previews), the
# fibre lobe, the reference render, an adaptive bake, the scene rendered from
# the bake, and a comparison sheet (reference | lookup | difference).
source "$(dirname "$0")/lib.sh"
install_packages
build_all
out="$CLOTHBAKE_ROOT/out/paper"
log "generating the paper cloth's volume texture into $out"
"$CLOTHBAKE_BUILD/baker/clothbake" volume "$CLOTHBAKE_ROOT/testscenes/paper/cloth.json" -o "$out"
log "fibre lobe of the paper's fibre (aspect 8) lit from 45 degrees"
"$CLOTHBAKE_BUILD/baker/clothbake" fiber --aspect 8 --tangent 1,0,0 --light 0,0.7071,0.7071 \
  --view 0,0,1 --samples 256 --plot "$out/fiber_lobe.png" >"$out/fiber.json"
scene="$CLOTHBAKE_ROOT/testscenes/paper/scene.json"
log "reference render of the paper scene"
"$CLOTHBAKE_BUILD/baker/clothbake" render "$scene" -o "$out/reference.exr" --png "$out/reference.png"
log "adaptive bake for the scene's camera"
"$CLOTHBAKE_BUILD/baker/clothbake" bake "$scene" -o "$out/bake" --adaptive --directions 16 >"$out/bake.json"
log "the scene rendered from the bake"
"$CLOTHBAKE_BUILD/baker/clothbake" lookup-render "$scene" "$out/bake" -o "$out/lookup.exr" --png "$out/lookup.png"
"$CLOTHBAKE_BUILD/baker/clothbake" compare "$out/reference.exr" "$out/lookup.exr" \
  --sheet "$out/compare.png" --json >"$out/compare.json"
log "done: $(cd "$out" && ls | tr '\n' ' ')"
