#!/usr/bin/env bash
# The WIF figures of README.md and docs/formats/wif.md, from the shipped files:
#   docs/images/wif_plaid.png        testscenes/wif/scene.json rendered (640 x 480,
#                                     32 spp) beside its drawdown (clothbake draft)
#   docs/images/wif_orientation.png  a small real draft's drawdown, tiled 3 x 3,
#                                     beside the volume's top view (3 x 3 repeats)
#   lab/wif_figures/wif_figures.sh CLOTHBAKE     (about 2 minutes)
set -euo pipefail
exe=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$root/docs/images
mkdir -p "$out"

# The plaid: the scene at 640 x 480 (the scene file keeps 320 x 240 for the test).
/usr/bin/python3 - "$root/testscenes/wif" "$tmp/scene.json" <<'PY'
import json, os, sys
src = sys.argv[1]
s = json.load(open(os.path.join(src, "scene.json")))
s["camera"]["resolution"] = [640, 480]
for o in s["objects"]:
    o["mesh"] = os.path.normpath(os.path.join(src, o["mesh"]))
    o["cloth"] = os.path.join(src, o["cloth"])
json.dump(s, open(sys.argv[2], "w"))
PY
"$exe" render "$tmp/scene.json" -o "$tmp/plaid.exr" --spp 32 --quiet
"$exe" draft "$root/testscenes/wif/plaid.json" -o "$tmp/plaid_draft" --block 2 >/dev/null
oiiotool "$tmp/plaid.exr" --ch R,G,B --colorconvert linear sRGB -d uint8 \
  "$tmp/plaid_draft/drawdown.png" --resize 480x480 --ch R,G,B \
  --mosaic 2x1 -o "$out/wif_plaid.png"

# Orientation: end 1 at x = 0 running right, pick 1 at y = 0 running up, in both.
real=$root/testscenes/wif/real/dbw_schort.wif
"$exe" volume "$real" -o "$tmp/small" >/dev/null
"$exe" draft "$real" -o "$tmp/small_draft" --block 5 >/dev/null
d=$tmp/small_draft/drawdown.png
oiiotool "$d" "$d" "$d" "$d" "$d" "$d" "$d" "$d" "$d" --mosaic 3x3 --resize 512x512 \
  --ch R,G,B -o "$tmp/tiled.png"
oiiotool "$tmp/small/top.png" --cut 0,26,767,793 --ch R,G,B --resize 512x512 -o "$tmp/top.png"
oiiotool "$tmp/tiled.png" "$tmp/top.png" --mosaic 2x1 -o "$out/wif_orientation.png"
echo "wrote $out/wif_plaid.png and $out/wif_orientation.png"
