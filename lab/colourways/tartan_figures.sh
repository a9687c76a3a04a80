#!/usr/bin/env bash
# README's tartan strip: ONE colour-free material of a 2/2 twill, rendered by
# lookup-render on the paper scene's folds in three tartan colourways, each
# given only as warp.colors / weft.colors in the scene's cloth spec (a
# 36-thread sett, mirrored, the same for warp and weft, as a tartan's is).
# Beside it, clothbake's reference render of the first colourway and its
# relative RMSE against the material's.
#   docs/images/material/tartan_strip.png
#   lab/colourways/tartan_figures.sh CLOTHBAKE     (about 6 minutes on 2 cores)
set -euo pipefail
exe=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$root/docs/images/material
mkdir -p "$out"

/usr/bin/python3 - "$root/testscenes/paper" "$tmp" <<'PY'
import json, os, shutil, sys
src, tmp = sys.argv[1], sys.argv[2]
# Tartan setts (thread counts per colour, half a sett; mirrored to a full one).
SETTS = {
    "hunting": [("navy", 4), ("black", 4), ("green", 8), ("black", 2)],
    "dress":   [("red", 8), ("navy", 2), ("red", 2), ("yellow", 2), ("red", 4)],
    "heather": [("cream", 6), ("grey", 4), ("rose", 2), ("grey", 6)],
}
COLOURS = {"navy": [0.02, 0.03, 0.12], "black": [0.015, 0.015, 0.02], "green": [0.02, 0.12, 0.05],
           "red": [0.45, 0.03, 0.03], "yellow": [0.60, 0.45, 0.05], "cream": [0.60, 0.55, 0.42],
           "grey": [0.18, 0.18, 0.19], "rose": [0.50, 0.16, 0.20]}
cloth = json.load(open(os.path.join(src, "cloth.json")))
cloth["weave"] = {"pattern": "twill_2_2"}
cloth.pop("resolution", None)  # 64 cells per 4-thread repeat
for name, sett in SETTS.items():
    half = [COLOURS[c] for c, n in sett for _ in range(n)]
    seq = half + half[::-1]
    d = os.path.join(tmp, name)
    os.makedirs(d)
    c = json.loads(json.dumps(cloth))
    c["warp"]["colors"] = seq
    c["weft"]["colors"] = seq
    json.dump(c, open(os.path.join(d, "cloth.json"), "w"))
    s = json.load(open(os.path.join(src, "scene.json")))
    for o in s["objects"]:
        o["repeats_per_uv"] = 20  # 80 threads per UV, as the paper scene's plain weave
    json.dump(s, open(os.path.join(d, "scene.json"), "w"))
    shutil.copy(os.path.join(src, "cloth.obj"), d)
PY
"$exe" material "$tmp/hunting/scene.json" -o "$tmp/material" --quiet >"$tmp/material.json"
for c in hunting dress heather; do
  "$exe" lookup-render "$tmp/$c/scene.json" "$tmp/material" -o "$tmp/$c.exr" --spp 16 --quiet
done
"$exe" render "$tmp/hunting/scene.json" -o "$tmp/reference.exr" --spp 16 --quiet
"$exe" compare "$tmp/reference.exr" "$tmp/hunting.exr" --json >"$tmp/cmp.json" || true
oiiotool "$tmp/hunting.exr" "$tmp/dress.exr" "$tmp/heather.exr" "$tmp/reference.exr" \
  --mosaic 4x1 --ch R,G,B --colorconvert linear sRGB -d uint8 -o "$out/tartan_strip.png"
/usr/bin/python3 - "$tmp" <<'PY'
import json, os, sys
t = sys.argv[1]
m = json.load(open(os.path.join(t, "material.json")))
c = json.load(open(os.path.join(t, "cmp.json")))
size = sum(os.path.getsize(os.path.join(t, "material", f)) for f in os.listdir(os.path.join(t, "material")))
print(json.dumps({"material_seconds": m.get("seconds"), "material_mb": size / 1e6,
                  "hunting_vs_reference_relative_rmse": c["relative_rmse"]}))
PY
