#!/usr/bin/env bash
# A cloth material against a per-scene bake of the same light:
# testscenes/slab (a homogeneous isotropic slab, one directional light at 45
# degrees, seen from straight above) rendered by lookup-render from a full
# per-scene bake and from a material of the same cloth. Both are estimates of
# the same march; the bound is derived from their noise: each texel averages
# spp marches whose jitter noise is about 1% (tests/core/bake/baker_test.cpp),
# so they must agree within 3% relative RMSE. The light (45 degrees) and the
# view (the normal) sit exactly on nodes of K = 5 grids (the material's light
# nodes on the plain square), so no interpolation enters; between light
# nodes the error is measured by Stability/MaterialGrazingLight (core tests). The material must also know nothing of the light: the
# same material under the light doubled renders twice as bright (within 1e-3).
#   material_cli.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
slab=$root/testscenes/slab/scene.json

"$exe" material "$slab" -o "$tmp/m" --texels 8 --directions 5 --light-directions 5 --spp 4 \
  --light-map square --quiet >"$tmp/m.json" || fail "material bake"
"$exe" bake "$slab" -o "$tmp/b" --texels 8 --directions 5 --spp 4 --quiet >/dev/null || fail "bake"
"$exe" lookup-render "$slab" "$tmp/m" -o "$tmp/m.exr" --spp 4 --quiet || fail "lookup-render material"
"$exe" lookup-render "$slab" "$tmp/b" -o "$tmp/b.exr" --spp 4 --quiet || fail "lookup-render bake"
"$exe" compare "$tmp/b.exr" "$tmp/m.exr" --max-relative-rmse 0.03 --json >"$tmp/cmp.json" ||
  fail "material against the per-scene bake: $(cat "$tmp/cmp.json")"
echo "ok   material against the per-scene bake: $(python3 -c "import json; print('relative RMSE %.4f' % json.load(open('$tmp/cmp.json'))['relative_rmse'])")"

# Light at render time: double the light's intensity, same material.
mkdir -p "$tmp/bright"
cp "$root/testscenes/slab/quad.obj" "$root/testscenes/slab/cloth.json" "$tmp/bright/"
sed 's/"intensity": 1.0/"intensity": 2.0/' "$slab" >"$tmp/bright/scene.json"
"$exe" lookup-render "$tmp/bright/scene.json" "$tmp/m" -o "$tmp/bright.exr" --spp 4 --quiet ||
  fail "lookup-render, brighter light"
/usr/bin/python3 - "$tmp/m.exr" "$tmp/bright.exr" <<'PY' || fail "a doubled light does not double the radiance"
import sys
import OpenImageIO as oiio
import numpy as np
a = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[..., :3]
b = oiio.ImageBuf(sys.argv[2]).get_pixels(oiio.FLOAT)[..., :3]
err = np.abs(b - 2 * a).max() / max(1e-9, np.abs(2 * a).max())
print(f"ok   doubled light: max relative deviation {err:.2e}")
sys.exit(0 if err < 1e-3 else 1)
PY
