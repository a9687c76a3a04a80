#!/usr/bin/env bash
# The bytes of every output kind on the paper and slab scenes, as sha256
# prefixes, for a refactoring that must change none of them:
#   scripts/dev/output_hashes.sh CLOTHBAKE [OUT_TSV]
# Runs render, bake (full and adaptive; every file of the folder, the
# manifest without its timings), lookup-render and volume (the cells hash:
# OpenVDB writes a random UUID into each file, docs/design/hardening.md). One
# thread and two threads must agree too. Then the cloth material:
# a small material of the paper cloth (every file of the folder, the
# manifest less its statistics), lookup-render of the paper scene from it
# at 4 spp, and with BLENDER set (or blender on the PATH) the headless
# Blender renders of both routes (Cycles, 4 samples, 2 threads; the EXR's
# pixels, not its header, which names the time). About 5 minutes on 2 cores.
set -euo pipefail
exe=$(realpath "$1")
out=${2:-/dev/stdout}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# Paths relative to the checkout: a bake's manifest records the scene's path,
# so two checkouts in different folders give the same bytes.
cd "$root"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
h() { sha256sum "$1" | cut -c1-16; }
# A bake folder's bytes: its EXRs, and the manifest less the statistics
# (seconds differ from run to run).
hbake() {
  local d=$1 acc=""
  for f in "$d"/*.exr; do acc+="$(basename "$f"):$(h "$f") "; done
  acc+="manifest:$(/usr/bin/python3 -c "
import json, sys, hashlib
m = json.load(open('$d/manifest.json')); m.pop('statistics', None)
print(hashlib.sha256(json.dumps(m, sort_keys=True).encode()).hexdigest()[:16])")"
  echo "$acc" | sha256sum | cut -c1-16
}
{
printf "output\tscene\tthreads\thash\n"
for scene in paper slab; do
  s=testscenes/$scene/scene.json
  for t in 1 2; do
    "$exe" render "$s" -o "$tmp/r.exr" --spp 2 --threads $t --quiet
    printf "render (2 spp)\t%s\t%s\t%s\n" $scene $t "$(h "$tmp/r.exr")"
  done
  "$exe" bake "$s" -o "$tmp/full" --directions 4 --texels 8 --spp 1 --threads 2 --quiet >/dev/null
  printf "bake full (K 4, R 8)\t%s\t2\t%s\n" $scene "$(hbake "$tmp/full")"
  "$exe" bake "$s" -o "$tmp/adaptive" --adaptive --directions 8 --spp 1 --threads 2 --quiet >/dev/null
  printf "bake adaptive (K 8)\t%s\t2\t%s\n" $scene "$(hbake "$tmp/adaptive")"
  "$exe" lookup-render "$s" "$tmp/adaptive" -o "$tmp/l.exr" --spp 4 --threads 2 --quiet
  printf "lookup-render (4 spp)\t%s\t2\t%s\n" $scene "$(h "$tmp/l.exr")"
  "$exe" volume "$(dirname "$s")/cloth.json" -o "$tmp/vol" --quiet >/dev/null 2>&1 || \
    "$exe" volume "$(dirname "$s")/cloth.json" -o "$tmp/vol" >/dev/null
  cells=$(ls "$tmp/vol" | tr '\n' ' ')
  acc=""
  for f in "$tmp"/vol/*; do
    case $f in
      *.vdb) ;;
      *.json) acc+="$(basename "$f"):$(/usr/bin/python3 -c "
import json, hashlib
m = json.load(open('$f')); m.pop('generate_seconds', None)
print(hashlib.sha256(json.dumps(m, sort_keys=True).encode()).hexdigest()[:16])") ";;
      *) acc+="$(basename "$f"):$(h "$f") ";;
    esac
  done
  printf "volume (PNGs, volume.json less its seconds; the VDB's cells hash is in it)\t%s\t-\t%s\n" $scene "$(echo "$acc" | sha256sum | cut -c1-16)"
  rm -rf "$tmp/full" "$tmp/adaptive" "$tmp/vol"
done
paper=testscenes/paper/scene.json
"$exe" material "$paper" -o "$tmp/mat" --texels 16 --directions 6 \
  --light-directions 6 --spp 1 --threads 2 --quiet >/dev/null
printf "material (R 16, K 6, KL 6, 1 spp)\tpaper\t2\t%s\n" "$(hbake "$tmp/mat")"
"$exe" lookup-render "$paper" "$tmp/mat" -o "$tmp/lm.exr" --spp 4 --threads 2 --quiet
printf "lookup-render from the material (4 spp)\tpaper\t2\t%s\n" "$(h "$tmp/lm.exr")"
blender=${BLENDER:-$(command -v blender || true)}
if [[ -n $blender ]]; then
  for route in exact cycles-lit; do
    "$blender" -b --factory-startup --python-exit-code 1 -P blender_addon/headless_render.py \
      -- "$paper" "$tmp/mat" "$tmp/b.exr" --samples 4 --threads 2 --route $route >/dev/null 2>&1
    printf "Blender headless, %s route (Cycles, 4 samples)\tpaper\t2\t%s\n" $route "$(/usr/bin/python3 -c "
import OpenImageIO as oiio, hashlib
print(hashlib.sha256(oiio.ImageInput.open('$tmp/b.exr').read_image('float').tobytes()).hexdigest()[:16])")"
  done
fi
} >"$out"
