#!/bin/bash
# How the view march's step moves the picture: the paper scene, and its cloth
# on a flat plane seen head-on, rendered at several steps against the finest.
#   lab/march_step/step_study.sh CLOTHBAKE OUT_DIR [SPP] [DRAFT.wif]
# With a draft, the cloth is that draft (generator seed 1) at 80 ends a UV, as
# lab/real_drafts/real_drafts.py puts it; without, the paper cloth.
# Prints, per view and step: the cloth's mean over the finest step's, the
# errors (lab/real_drafts/means.py) and the render's seconds. Re-running
# skips the renders already made. About 6 minutes on 2 cores at 16 spp for
# the paper cloth, 10 for a real draft.
set -euo pipefail
exe=$(realpath "$1")
out=$2
spp=${3:-16}
wif=${4:+$(realpath "$4")}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
py=/usr/bin/python3
mkdir -p "$out"
cloth_sets=()
if [ -n "$wif" ]; then
  "$exe" draft "$wif" -o "$out/draft" >/dev/null
  ends=$("$py" -c 'import json, sys; print(json.load(open(sys.argv[1]))["ends"])' "$out/draft/draft.json")
  printf '{"name": "draft", "weave": {"wif": "%s"}, "seed": 1}\n' "$wif" > "$out/cloth.json"
  cloth_sets=("object.cloth=\"$out/cloth.json\"" "object.repeats_per_uv=$("$py" -c "print(80 / $ends)")")
fi

# A copy of the paper scene with fields of "render" or the camera set.
edit() {
  "$py" - "$root/testscenes/paper" "$@" <<'PY'
import json, os, sys
src_dir, dst, *sets = sys.argv[1:]
s = json.load(open(os.path.join(src_dir, "scene.json")))
obj = s["objects"][0]
for key in ("mesh", "cloth"):
    obj[key] = os.path.join(src_dir, obj[key])
for kv in sets:
    key, value = kv.split("=", 1)
    if "." in key:
        where, field = key.split(".", 1)
        node = obj if where == "object" else s.setdefault(where, {})
        node[field] = json.loads(value)
    else:
        s[key] = json.loads(value)
json.dump(s, open(dst, "w"), indent=1)
PY
}

head_on='{"position": [0.3, -0.5, 3.2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 44, "fov_axis": "horizontal", "resolution": [320, 200]}'
steps="0.0625 0.125 0.25 0.5 1.0"
for view in paper flat_head_on; do
  echo "== $view ($spp spp; against step 0.0625)"
  for step in $steps; do
    sets=("render.step_cells=$step" "render.spp=$spp" "${cloth_sets[@]}")
    [ $view = flat_head_on ] && sets+=("object.mesh=\"$root/testscenes/flat/cloth.obj\"" "camera=$head_on")
    edit "$out/${view}_$step.json" "${sets[@]}"
    if [ ! -f "$out/${view}_$step.exr" ]; then
      start=$(date +%s.%N)
      "$exe" render "$out/${view}_$step.json" -o "$out/${view}_$step.exr" --quiet
      echo "$(echo "$(date +%s.%N) - $start" | bc)" > "$out/${view}_$step.seconds"
    fi
  done
  for step in $steps; do
    printf 'step %s (%.1f s): ' "$step" "$(cat "$out/${view}_$step.seconds")"
    "$py" "$root/lab/real_drafts/means.py" "$out/${view}_0.0625.exr" "$out/${view}_$step.exr" |
      sed 's/^[^:]*: //'
  done
done
