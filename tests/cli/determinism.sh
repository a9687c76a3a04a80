#!/usr/bin/env bash
# Determinism (docs/design/hardening.md): render, bake (full, adaptive, a --quads
# slice), material and lookup-render (of a bake and of a material) write the same bytes with 1 and 2 threads and across
# two runs of each: four runs per command, every output file compared with
# cmp. Manifests are compared without their wall-clock fields
# (statistics.*seconds*, manifest_without_times.py); everything else in them,
# and every EXR and PNG, byte for byte.
#   determinism.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# The paper scene (64 quads, a woven volume) at a quarter of its resolution.
python3 - "$root/testscenes/paper" "$tmp/scene.json" <<'PY'
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
s = json.load(open(os.path.join(src, "scene.json")))
s["camera"]["resolution"] = [r // 4 for r in s["camera"]["resolution"]]
for o in s["objects"]:
    for key in ("mesh", "cloth"):
        if isinstance(o.get(key), str):
            o[key] = os.path.join(src, o[key])
json.dump(s, open(dst, "w"), indent=2)
PY
scene=$tmp/scene.json
bake=(--directions 3 --texels 4 --spp 1)

# Runs one command four times (threads 1 and 2, twice each) into $tmp/NAME/RUN
# (the command's {} stands for that folder) and compares every file.
check() {  # name, command with {} for the output folder...
  local name=$1; shift
  local runs=(t1a t1b t2a t2b) run
  for run in "${runs[@]}"; do
    local dir=$tmp/$name/$run threads=${run:1:1}
    mkdir -p "$dir"
    "${@//\{\}/$dir}" --threads "$threads" --quiet >/dev/null 2>"$dir.err" ||
      fail "$name ($run): $(cat "$dir.err")"
  done
  local first=$tmp/$name/t1a files=0 f rel
  while IFS= read -r f; do
    rel=${f#"$first"/}
    for run in "${runs[@]:1}"; do
      local other=$tmp/$name/$run/$rel
      [[ -f $other ]] || fail "$name: $rel missing in run $run"
      if [[ $rel == */manifest.json || $rel == manifest.json ]]; then
        cmp -s <(python3 "$root/tests/cli/manifest_without_times.py" "$f") \
          <(python3 "$root/tests/cli/manifest_without_times.py" "$other") ||
          fail "$name: $rel differs (times aside) between t1a and $run"
      else
        cmp -s "$f" "$other" || fail "$name: $rel differs between t1a and $run"
      fi
    done
    files=$((files + 1))
  done < <(find "$first" -type f | LC_ALL=C sort)
  for run in "${runs[@]:1}"; do
    [[ $(cd "$first" && find . -type f | sort) == $(cd "$tmp/$name/$run" && find . -type f | sort) ]] ||
      fail "$name: run $run wrote other files than t1a"
  done
  [[ $files -ge 1 ]] || fail "$name: no output files"
  echo "ok   $name: $files files identical over 4 runs (threads 1, 1, 2, 2): $(cd "$first" && find . -type f | sed 's|^\./||' | sort | tr '\n' ' ')"
}

check render "$exe" render "$scene" -o {}/r.exr --png {}/r.png --spp 2
check bake_full "$exe" bake "$scene" -o {}/b "${bake[@]}"
check bake_adaptive "$exe" bake "$scene" -o {}/b --adaptive --directions 3 --spp 1
check bake_quads "$exe" bake "$scene" -o {}/b "${bake[@]}" --quads 10-30
check lookup_render "$exe" lookup-render "$scene" "$tmp/bake_full/t1a/b" -o {}/r.exr --png {}/r.png --spp 2
check lookup_render_adaptive "$exe" lookup-render "$scene" "$tmp/bake_adaptive/t1a/b" -o {}/r.exr --spp 2
# The cloth material: the bake's folder and a render from it.
check material "$exe" material "$scene" -o {}/m --texels 8 --directions 3 --light-directions 3 --spp 1
check lookup_render_material "$exe" lookup-render "$scene" "$tmp/material/t1a/m" -o {}/r.exr --spp 2
