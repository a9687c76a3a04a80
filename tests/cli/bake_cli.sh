#!/usr/bin/env bash
# clothbake bake / lookup-render / merge from the command line:
#  - bad input: exit status non-zero, a message naming the file or option, no output;
#  - partial bakes (--quads) merged are byte-identical to a whole bake.
set -u
exe=$1 root=$2
paper=$root/testscenes/paper/scene.json
slab=$root/testscenes/slab/scene.json
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
small=(--directions 3 --texels 4 --spp 1 --quiet)

refused() {  # expected message, output path that must not exist, command...
  local expect=$1 out=$2; shift 2
  "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  [[ $rc -ne 0 ]] || fail "$* succeeded"
  grep -qF -- "$expect" "$tmp/stderr" || fail "$*: expected '$expect', got: $(cat "$tmp/stderr")"
  [[ ! -e $out ]] || fail "$*: left $out behind"
  echo "ok (exit $rc): $(head -1 "$tmp/stderr")"
}
refused "cannot open file" "$tmp/b1" "$exe" bake "$tmp/nope.json" -o "$tmp/b1"
refused "--quads: expected A-B" "$tmp/b2" "$exe" bake "$paper" -o "$tmp/b2" --quads 9-2 "${small[@]}"
refused "selects no quad" "$tmp/b3" "$exe" bake "$paper" -o "$tmp/b3" --quads 100-200 "${small[@]}"
refused "--texels: the lookup would need" "$tmp/b4" "$exe" bake "$paper" -o "$tmp/b4" --directions 64 --texels 4096 --quiet
refused "--directions" "$tmp/b5" "$exe" bake "$paper" -o "$tmp/b5" --directions 1 --quiet
refused "manifest.json" "$tmp/r1.exr" "$exe" lookup-render "$paper" "$tmp/missing_bake" -o "$tmp/r1.exr" --quiet

# A slab bake read with the paper scene: another scene.
"$exe" bake "$slab" -o "$tmp/slab_bake" "${small[@]}" >/dev/null || fail "slab bake"
refused "baked for another scene" "$tmp/r2.exr" "$exe" lookup-render "$paper" "$tmp/slab_bake" -o "$tmp/r2.exr" --quiet
# A truncated manifest.
cp -r "$tmp/slab_bake" "$tmp/cut_bake"
head -c 200 "$tmp/slab_bake/manifest.json" >"$tmp/cut_bake/manifest.json"
refused "manifest.json" "$tmp/r3.exr" "$exe" lookup-render "$slab" "$tmp/cut_bake" -o "$tmp/r3.exr" --quiet
# A truncated lookup image.
cp -r "$tmp/slab_bake" "$tmp/trunc_bake"
f=$(ls "$tmp/trunc_bake"/*.exr | head -1)
head -c 300 "$f" >"$f.cut" && mv "$f.cut" "$f"
refused "$(basename "$f")" "$tmp/r4.exr" "$exe" lookup-render "$slab" "$tmp/trunc_bake" -o "$tmp/r4.exr" --quiet

# Merge on the paper scene at tiny settings.
"$exe" bake "$paper" -o "$tmp/whole1" "${small[@]}" --threads 1 >/dev/null || fail "bake 1 thread"
"$exe" bake "$paper" -o "$tmp/part_a" "${small[@]}" --quads 0-20 >/dev/null || fail "part a"
"$exe" bake "$paper" -o "$tmp/part_b" "${small[@]}" --quads 21-63 >/dev/null || fail "part b"
"$exe" merge "$tmp/part_a" "$tmp/part_b" -o "$tmp/merged" >/dev/null || fail "merge"
n=0
for exr in "$tmp/whole1"/*.exr; do
  name=$(basename "$exr")
  cmp -s "$exr" "$tmp/merged/$name" || fail "$name differs between the merged parts and the whole bake"
  n=$((n + 1))
done
[[ $n -ge 1 ]] || fail "no lookup images"
echo "ok: $n lookup images identical for merged partial bakes and the whole bake"
# (1 and 2 threads, two runs, every command: determinism.sh, ctest cli.deterministic.)
