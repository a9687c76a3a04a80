#!/usr/bin/env bash
# A scene whose cloth is a WIF draft (testscenes/wif/scene.json: a real
# Handweaving.net draft recoloured into a plaid by weft.colors) through the
# reference renderer and the per-scene baker: lookup-render of the adaptive
# bake against the reference, mean within 1 % and 8 x 8-pixel blocks within
# 3 % relative RMSE (the bounds of cli.lights). The cloth is generated at 4
# cells per thread instead of the default 8 to keep the test short.
#   wif_plaid.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
/usr/bin/python3 - "$root/testscenes/wif" "$tmp" <<'PY'
import json, os, sys
src, out = sys.argv[1], sys.argv[2]
spec = json.load(open(os.path.join(src, "plaid.json")))
spec["weave"]["wif"] = os.path.join(src, spec["weave"]["wif"])
spec["resolution"] = {"cells_per_thread": 4}
json.dump(spec, open(os.path.join(out, "plaid.json"), "w"))
scene = json.load(open(os.path.join(src, "scene.json")))
for o in scene["objects"]:
    o["mesh"] = os.path.normpath(os.path.join(src, o["mesh"]))
    o["cloth"] = os.path.join(out, "plaid.json")
json.dump(scene, open(os.path.join(out, "scene.json"), "w"), indent=1)
PY
scene=$tmp/scene.json
"$exe" render "$scene" -o "$tmp/ref.exr" --spp 64 --quiet || fail "reference render"
"$exe" bake "$scene" -o "$tmp/b" --adaptive --quiet >/dev/null || fail "per-scene bake"
"$exe" lookup-render "$scene" "$tmp/b" -o "$tmp/b.exr" --spp 64 --quiet || fail "lookup-render"
/usr/bin/python3 - "$tmp/ref.exr" "$tmp/b.exr" <<'PY' || fail "the bake of a WIF cloth against its reference"
import sys
import OpenImageIO as oiio
import numpy as np
def load(p):
    return oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
def pooled(a, k=8):
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    return a[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
r, b = load(sys.argv[1]), load(sys.argv[2])
assert r.mean() > 0.01, "the reference is black"
mean = b.mean() / r.mean() - 1
R, B = pooled(r), pooled(b)
blocks = np.sqrt(((B - R) ** 2).mean()) / np.sqrt((R ** 2).mean())
pixel = np.sqrt(((b - r) ** 2).mean()) / np.sqrt((r ** 2).mean())
print(f"ok?  WIF plaid, per-scene bake: mean {100 * mean:+.2f} %, 8x8 blocks {100 * blocks:.2f} %, per pixel {100 * pixel:.2f} %")
sys.exit(0 if abs(mean) <= 0.01 and blocks <= 0.03 else 1)
PY
echo "ok   a WIF cloth renders and bakes"
