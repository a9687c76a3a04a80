#!/usr/bin/env bash
# The node group's view parallax (docs/design/material.md, "View nodes and
# parallax"): testscenes/dome, where the shift matters (a thick cloth seen
# from low), a small material baked with it (R 16, K 16, 1 spp), Blender's
# headless exact route (Cycles, 16 samples, seeds 1 and 2) against
# lookup-render of the same material, and of a copy whose manifest says
# parallax_depth_mm 0 (the same tables read unshifted):
# - with: relative RMSE of the two renders' mean at most 3 sigma + 1.5 %,
#   sigma the mean's own noise (|seed 1 - seed 2| / 2 over the mean);
# - without: at least 1.15 x that (measured at 32 samples: 4.78 % against
#   6.32 %); a group that ignored the shift would swap the two.
#   material_parallax.sh BLENDER CLOTHBAKE SOURCE_DIR
set -u
blender=$1 exe=$2 src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=$src/testscenes/dome/scene.json

"$exe" material "$scene" -o "$tmp/m" --texels 16 --spp 1 --quiet >/dev/null || fail "material bake"
cp -r "$tmp/m" "$tmp/flat"
/usr/bin/python3 - "$tmp/m/manifest.json" "$tmp/flat/manifest.json" <<'PY' || fail "the copy"
import json, sys
m = json.load(open(sys.argv[1]))
assert m["parallax_depth_mm"] > 0, "the dome's fitted depth is 0"
print(f"fitted depth {m['parallax_depth_mm']:.4f} mm of {m['repeat_mm'][2]:.3f}")
m["parallax_depth_mm"] = 0.0
json.dump(m, open(sys.argv[2], "w"), indent=2)
PY
for m in m flat; do
  "$exe" lookup-render "$scene" "$tmp/$m" -o "$tmp/lookup_$m.exr" --spp 64 --quiet ||
    fail "lookup-render $m"
done
for seed in 1 2; do
  "$blender" -b --factory-startup --python-exit-code 1 -P "$src/blender_addon/headless_render.py" \
    -- "$scene" "$tmp/m" "$tmp/blender_$seed.exr" --samples 16 --seed $seed \
    >"$tmp/blender_$seed.log" 2>&1 || { tail -20 "$tmp/blender_$seed.log"; fail "Blender seed $seed"; }
done
/usr/bin/python3 - "$tmp" <<'PY' || fail "the parallax figures"
import sys
import numpy as np
import OpenImageIO as oiio
tmp = sys.argv[1]
def load(name):
    return oiio.ImageBuf(f"{tmp}/{name}").get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
a, b = load("blender_1.exr"), load("blender_2.exr")
mean = 0.5 * (a + b)
sigma = np.sqrt(((a - b) ** 2).mean()) / 2 / mean.mean()
def rel(ref):
    return np.sqrt(((mean - ref) ** 2).mean()) / ref.mean()
with_shift, without = rel(load("lookup_m.exr")), rel(load("lookup_flat.exr"))
bound = 3 * sigma + 0.015
print(f"Blender (mean of 2 x 16 samples) against lookup-render: with the shift {with_shift:.4f} "
      f"(bound {bound:.4f}, noise {sigma:.4f}), read unshifted {without:.4f}")
sys.exit(0 if with_shift <= bound and without >= 1.15 * with_shift else 1)
PY
