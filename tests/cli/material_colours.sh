#!/usr/bin/env bash
# Colours at render time (issue 24): one colour-free material of the paper
# cloth (tiny settings), rendered by lookup-render in the paper scene's own
# colours, in another weft colour and with a 3-end warp stripe (a 6-end cloth
# from a 2-end material), without baking again; and refused, naming the
# field and writing nothing, for a scene whose cloth differs in anything but
# colour.
#   material_colours.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
paper=$root/testscenes/paper

# A copy of the paper scene whose cloth spec is edited by a Python expression.
variant() {  # NAME EXPR
  mkdir -p "$tmp/$1"
  cp "$paper/scene.json" "$paper/cloth.obj" "$tmp/$1/"
  /usr/bin/python3 - "$paper/cloth.json" "$tmp/$1/cloth.json" "$2" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(c, open(sys.argv[2], "w"))
PY
}
variant same "pass"
variant blue "c['weft']['color'] = [0.05, 0.1, 0.5]"
variant stripe "c['warp']['colors'] = [[0.6, 0.09, 0.08], [0.8, 0.75, 0.6], [0.1, 0.3, 0.1]]"
variant spacing "c['warp']['spacing_mm'] = 0.55"
variant seed "c['seed'] = 2"

"$exe" material "$tmp/same/scene.json" -o "$tmp/m" --texels 8 --directions 4 --light-directions 4 \
  --spp 1 --quiet >/dev/null || fail "material bake"
/usr/bin/python3 -c "
import json,sys; m=json.load(open('$tmp/m/manifest.json'))
sys.exit(0 if m['version'] == 2 and m['parts'] == 'specular-warp-weft' else 1)" ||
  fail "a fibre-shaded spec cloth bakes colour-free parts by default"
for v in same blue stripe; do
  "$exe" lookup-render "$tmp/$v/scene.json" "$tmp/m" -o "$tmp/$v.exr" --spp 2 --quiet ||
    fail "lookup-render in the colours of '$v'"
done
# The weft turned blue: the image's blue over red rises; the stripe's cream
# and green ends: green over red rises. Both measured on the same pixels.
/usr/bin/python3 - "$tmp" <<'PY' || fail "the scene's colours are not the ones rendered"
import sys
import numpy as np
import OpenImageIO as oiio
t = sys.argv[1]
px = {v: oiio.ImageBuf(f"{t}/{v}.exr").get_pixels(oiio.FLOAT) for v in ("same", "blue", "stripe")}
cloth = px["same"][..., 3] > 0.95
mean = {v: p[cloth][:, :3].mean(0) for v, p in px.items()}
b_r = {v: m[2] / m[0] for v, m in mean.items()}
g_r = {v: m[1] / m[0] for v, m in mean.items()}
print("ok   mean RGB over the cloth: " + ", ".join(f"{v} {np.round(m, 4)}" for v, m in mean.items()))
ok = b_r["blue"] > 2 * b_r["same"] and g_r["stripe"] > 1.3 * g_r["same"]
sys.exit(0 if ok else 1)
PY
# The stripe written as a WIF writes it: the plain weave's draft over the
# 6 ends and 6 picks of the colours' repeat, 32 cells per thread written out
# for it, repeats_per_uv counting that written repeat (3 of the weave's).
# Cut to its weave, it is the same colour-free cloth: the material takes it
# and renders the same image.
variant written "
c['warp']['colors'] = [[0.6, 0.09, 0.08], [0.8, 0.75, 0.6], [0.1, 0.3, 0.1]]
c['weave'] = {'draft': [[(r + e + 1) % 2 for e in range(6)] for r in range(6)]}
c['resolution'].update(cells_x=192, cells_y=192)"
/usr/bin/python3 - "$tmp/written/scene.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["objects"][0]["repeats_per_uv"] = s["objects"][0]["repeats_per_uv"] / 3
json.dump(s, open(sys.argv[1], "w"))
PY
"$exe" lookup-render "$tmp/written/scene.json" "$tmp/m" -o "$tmp/written.exr" --spp 2 --quiet \
  2>"$tmp/written.err" || fail "the stripe written over its colour repeat: $(cat "$tmp/written.err")"
"$exe" compare "$tmp/stripe.exr" "$tmp/written.exr" --max-relative-rmse 1e-4 --json >"$tmp/w.json" ||
  fail "the stripe written over its colour repeat renders differently: $(cat "$tmp/w.json")"
echo "ok   a draft written over its colour repeat is the same material: $(tr -d ' \n' <"$tmp/w.json" | grep -o '"relative_rmse":[^,]*')"

# Anything but colour: refused, the field named, no image written.
for case in "spacing:objects[0].cloth.warp.spacing_mm" "seed:objects[0].cloth.seed"; do
  v=${case%%:*} field=${case#*:}
  if "$exe" lookup-render "$tmp/$v/scene.json" "$tmp/m" -o "$tmp/$v.exr" --quiet 2>"$tmp/$v.err"; then
    fail "a cloth that differs in $v was accepted"
  fi
  grep -qF "$field" "$tmp/$v.err" || fail "the refusal does not name $field: $(cat "$tmp/$v.err")"
  [ ! -e "$tmp/$v.exr" ] || fail "a refused render wrote $v.exr"
  echo "ok   refused: $(head -c 200 "$tmp/$v.err")"
done
echo "ok   colours at render time"
