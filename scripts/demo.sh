#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the bundled paper
# scene: for now, the paper cloth's volume texture (VDB + previews) in out/paper/.
source "$(dirname "$0")/lib.sh"
install_packages
build_all
out="$CLOTHBAKE_ROOT/out/paper"
log "generating the paper cloth's volume texture into $out"
"$CLOTHBAKE_BUILD/baker/clothbake" volume "$CLOTHBAKE_ROOT/testscenes/paper/cloth.json" -o "$out"
log "fibre lobe of the paper's fibre (aspect 8) lit from 45 degrees"
"$CLOTHBAKE_BUILD/baker/clothbake" fiber --aspect 8 --tangent 1,0,0 --light 0,0.7071,0.7071 \
  --view 0,0,1 --samples 256 --plot "$out/fiber_lobe.png" >"$out/fiber.json"
log "done: $(cd "$out" && ls | tr '\n' ' ')"
