#!/usr/bin/env bash
# The curvature case of the stability suite (docs/design/stability.md,
# "Curved cloth at grazing views"): testscenes/dome, the paper's weave on a
# spherical cap seen from low over its rim, its flanks and far side at
# grazing views. lookup-render from a material baked at the defaults against
# the reference renderer at 256 samples:
# - per pixel (compare's relative RMSE): held at 11.5 % (measured 10.93 %
#   with the view parallax of the default bake, 12.47 % without it; the
#   issue's target of 8 % is not met here, see docs/design/stability.md);
# - over 8 x 8-pixel blocks (RMSE over RMS): held at 3 % (measured 2.3 %):
#   the error is at the scale of the weave, not a shading trend;
# - no worse than the per-scene adaptive bake of the same scene (22.0 %).
# The renders and bakes are deterministic, so the figures are too.
#   dome_material.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=$root/testscenes/dome/scene.json

"$exe" render "$scene" -o "$tmp/ref.exr" --spp 256 --quiet || fail "reference render"
"$exe" material "$scene" -o "$tmp/m" --quiet >/dev/null || fail "material bake"
"$exe" lookup-render "$scene" "$tmp/m" -o "$tmp/m.exr" --spp 64 --quiet || fail "lookup-render, material"
"$exe" bake "$scene" -o "$tmp/b" --adaptive --quiet >/dev/null || fail "adaptive bake"
"$exe" lookup-render "$scene" "$tmp/b" -o "$tmp/b.exr" --spp 64 --quiet || fail "lookup-render, bake"
"$exe" compare "$tmp/ref.exr" "$tmp/m.exr" --json >"$tmp/m.json"
"$exe" compare "$tmp/ref.exr" "$tmp/b.exr" --json >"$tmp/b.json"
/usr/bin/python3 - "$tmp" <<'PY' || fail "the dome's figures"
import json, sys
import OpenImageIO as oiio
import numpy as np
tmp = sys.argv[1]
m = json.load(open(f"{tmp}/m.json"))["relative_rmse"]
b = json.load(open(f"{tmp}/b.json"))["relative_rmse"]
def load(p):
    return oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
def pooled(a, k=8):
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    return a[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
r, t = pooled(load(f"{tmp}/ref.exr")), pooled(load(f"{tmp}/m.exr"))
blocks = np.sqrt(((t - r) ** 2).mean()) / np.sqrt((r ** 2).mean())
print(f"dome: material {m:.4f} per pixel, {blocks:.4f} over 8x8 blocks; per-scene bake {b:.4f}")
ok = m <= 0.115 and blocks <= 0.03 and m <= b
sys.exit(0 if ok else 1)
PY
