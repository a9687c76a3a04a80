#!/usr/bin/env bash
# Spot and area lights through every route: testscenes/lights (the
# paper's weave on the flat cloth, a spot whose soft edge crosses it and a
# rectangular area light beside it).
# - lookup-render from a material baked at the defaults (the material knows
#   no light) must be within 8 % relative RMSE of the reference renderer at
#   256 samples, the issue's bound (measured 6.9 %; the reference's own noise
#   at 256 samples is about 1 %, docs/design/blender-nodes.md);
# - the per-scene adaptive bake through lookup-render: its mean within 1 %
#   of the reference's and 8 x 8-pixel blocks within 3 % (RMSE over RMS;
#   measured 0.4 % and 1.9 %; per pixel it errs 10 % here, with a sun alone
#   too: the bake's texels at this grazing view, not the lights);
# - a spot aimed away from the cloth and an area light facing away light
#   nothing: the reference and lookup-render give the background (to 1e-6).
#   lights_cli.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=$root/testscenes/lights/scene.json

"$exe" render "$scene" -o "$tmp/ref.exr" --spp 256 --quiet || fail "reference render"
"$exe" material "$scene" -o "$tmp/m" --quiet >/dev/null || fail "material bake"
"$exe" lookup-render "$scene" "$tmp/m" -o "$tmp/m.exr" --spp 64 --quiet || fail "lookup-render"
"$exe" compare "$tmp/ref.exr" "$tmp/m.exr" --max-relative-rmse 0.08 --json >"$tmp/cmp.json" ||
  fail "material under spot and area lights against the reference: $(cat "$tmp/cmp.json")"
echo "ok   material, spot + area: relative RMSE $(/usr/bin/python3 -c "import json; print('%.4f' % json.load(open('$tmp/cmp.json'))['relative_rmse'])")"

"$exe" bake "$scene" -o "$tmp/b" --adaptive --quiet >/dev/null || fail "per-scene bake"
"$exe" lookup-render "$scene" "$tmp/b" -o "$tmp/b.exr" --spp 64 --quiet || fail "lookup-render, bake"
/usr/bin/python3 - "$tmp/ref.exr" "$tmp/b.exr" <<'PY' || fail "per-scene bake under spot and area lights"
import sys
import OpenImageIO as oiio
import numpy as np
def load(p):
    return oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
def pooled(a, k=8):
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    return a[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
r, b = load(sys.argv[1]), load(sys.argv[2])
mean = b.mean() / r.mean() - 1
R, B = pooled(r), pooled(b)
blocks = np.sqrt(((B - R) ** 2).mean()) / np.sqrt((R ** 2).mean())
print(f"     per-scene bake, spot + area: mean {100 * mean:+.2f} %, 8x8 blocks {100 * blocks:.2f} %")
sys.exit(0 if abs(mean) <= 0.01 and blocks <= 0.03 else 1)
PY

# Lights that reach nothing: the spot turned up, the area light facing up.
mkdir -p "$tmp/away"
/usr/bin/python3 - "$scene" "$tmp/away/scene.json" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
here = os.path.dirname(os.path.abspath(sys.argv[1]))
for o in s["objects"]:
    o["mesh"] = os.path.join(here, o["mesh"])
    o["cloth"] = os.path.join(here, o["cloth"])
for light in s["lights"]:
    light["direction"] = [-c for c in light["direction"]]
json.dump(s, open(sys.argv[2], "w"), indent=1)
PY
"$exe" render "$tmp/away/scene.json" -o "$tmp/away_ref.exr" --spp 4 --quiet || fail "render, away"
"$exe" lookup-render "$tmp/away/scene.json" "$tmp/m" -o "$tmp/away_m.exr" --spp 4 --quiet ||
  fail "lookup-render, away"
/usr/bin/python3 - "$tmp/away_ref.exr" "$tmp/away_m.exr" <<'PY' || fail "lights facing away light the cloth"
import sys
import OpenImageIO as oiio
import numpy as np
for path in sys.argv[1:]:
    px = oiio.ImageBuf(path).get_pixels(oiio.FLOAT)
    rgb, alpha = px[..., :3], px[..., 3:4]
    # Where cloth covers the pixel it is black; the background shows through the rest.
    background = np.array([0.05, 0.05, 0.06], dtype=np.float32) * (1 - alpha)
    err = np.abs(rgb - background).max()
    assert alpha.max() > 0.5, f"{path}: no cloth in view"
    print(f"ok   lights facing away: {path.split('/')[-1]} max deviation {err:.1e}")
    if err > 1e-6:
        sys.exit(1)
PY
