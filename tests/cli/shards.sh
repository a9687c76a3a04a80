#!/usr/bin/env bash
# Sharded bakes (docs/guide/farm.md): a material in 3 parts merged has
# every byte of the unsharded bake, whatever order the parts are given in; a
# per-scene bake in 2 parts (--shard) merged equals the whole bake; and a
# part is refused by lookup-render, a missing, doubled or foreign part by
# merge, each naming the field and writing nothing.
#   shards.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=$root/testscenes/paper/scene.json
small=(--texels 8 --directions 4 --light-directions 4 --spp 1 --quiet)

"$exe" material "$scene" -o "$tmp/whole" "${small[@]}" >/dev/null || fail "whole material"
for i in 1 2 3; do
  "$exe" material "$scene" -o "$tmp/p$i" "${small[@]}" --shard "$i/3" >/dev/null || fail "part $i"
done
"$exe" material "$scene" -o "$tmp/seed2" "${small[@]}" --seed 2 --shard 2/3 >/dev/null ||
  fail "part with another seed"
"$exe" merge "$tmp/p3" "$tmp/p1" "$tmp/p2" -o "$tmp/merged" >/dev/null || fail "merge"
n=0
for f in "$tmp"/whole/*; do
  cmp -s "$f" "$tmp/merged/$(basename "$f")" || fail "merged $(basename "$f") differs from the whole bake"
  n=$((n + 1))
done
[ "$n" -ge 4 ] || fail "the whole material has only $n files"
[ "$(ls "$tmp/merged" | wc -l)" = "$n" ] || fail "the merged folder has other files"

# --estimate with --shard: each part's estimate is of its views alone (the
# three parts' views and cost shares add up to the whole's), writing nothing.
for i in 1 2 3; do
  "$exe" material "$scene" -o "$tmp/est" "${small[@]}" --shard "$i/3" --estimate >"$tmp/est$i.json" ||
    fail "--estimate of part $i"
done
"$exe" material "$scene" -o "$tmp/est" "${small[@]}" --estimate >"$tmp/est.json" || fail "--estimate"
[ ! -e "$tmp/est" ] || fail "--estimate wrote $tmp/est"
/usr/bin/python3 - "$tmp"/est.json "$tmp"/est1.json "$tmp"/est2.json "$tmp"/est3.json <<'PY' ||
import json, sys
whole, *parts = (json.load(open(p)) for p in sys.argv[1:])
views = sum(p["view_nodes"] for p in parts)
share = sum(p["shard"]["cost_share"] for p in parts)
rays = sum(p["rays"] for p in parts)
ok = (views == whole["view_nodes"] and abs(share - 1) < 1e-9 and rays == whole["rays"]
      and all(p["shard"]["of"] == 3 and p["shard"]["whole_view_nodes"] == whole["view_nodes"]
              for p in parts)
      and "shard" not in whole)
print(f"  parts' views {views} of {whole['view_nodes']}, cost shares sum {share:.12f}, rays {rays} of {whole['rays']}")
sys.exit(0 if ok else 1)
PY
  fail "the parts' estimates do not add up to the whole's (above)"

refuse() {  # WHAT FIELD OUT -- COMMAND...
  local what=$1 field=$2 out=$3
  shift 4
  "$@" >"$tmp/out.txt" 2>"$tmp/err.txt" && fail "$what: accepted"
  grep -q -- "$field" "$tmp/err.txt" || fail "$what: the error does not name $field: $(cat "$tmp/err.txt")"
  [ ! -e "$out" ] || fail "$what: $out was written"
}
refuse "lookup-render of a part" "shard.part" "$tmp/x.exr" -- \
  "$exe" lookup-render "$scene" "$tmp/p1" -o "$tmp/x.exr" --spp 1 --quiet
refuse "a missing part" "shard.part" "$tmp/m1" -- "$exe" merge "$tmp/p1" "$tmp/p2" -o "$tmp/m1"
refuse "a doubled part" "shard.part" "$tmp/m2" -- \
  "$exe" merge "$tmp/p1" "$tmp/p2" "$tmp/p2" -o "$tmp/m2"
refuse "a part of another seed" "seed" "$tmp/m3" -- \
  "$exe" merge "$tmp/p1" "$tmp/seed2" "$tmp/p3" -o "$tmp/m3"
refuse "a whole material among the parts" "shard" "$tmp/m4" -- \
  "$exe" merge "$tmp/p1" "$tmp/whole" "$tmp/p3" -o "$tmp/m4"
refuse "part 4 of 3" "--shard" "$tmp/p4" -- \
  "$exe" material "$scene" -o "$tmp/p4" "${small[@]}" --shard 4/3

# The per-scene bake: two parts by --shard, merged, against the whole bake.
bake=(--texels 4 --directions 2 --spp 1 --quiet)
"$exe" bake "$scene" -o "$tmp/lw" "${bake[@]}" >/dev/null || fail "whole bake"
for i in 1 2; do
  "$exe" bake "$scene" -o "$tmp/l$i" "${bake[@]}" --shard "$i/2" >/dev/null || fail "bake part $i"
done
"$exe" merge "$tmp/l2" "$tmp/l1" -o "$tmp/lm" >/dev/null || fail "merge of the bake parts"
for f in "$tmp"/lw/*; do
  b=$(basename "$f")
  [ "$b" = manifest.json ] && continue  # below
  cmp -s "$f" "$tmp/lm/$b" || fail "merged bake's $b differs from the whole bake"
done
# The manifest: equal to the whole bake's but for "statistics" (seconds).
/usr/bin/python3 - "$tmp/lw/manifest.json" "$tmp/lm/manifest.json" <<'PY' || fail "merged bake's manifest differs (above)"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for m in (a, b):
    m.pop("statistics", None)
diff = [k for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
if diff:
    print("  fields that differ:", ", ".join(diff), [(a.get(k), b.get(k)) for k in diff][:3])
sys.exit(1 if diff else 0)
PY
echo "OK: 3 material parts merge to the whole bake's $n files byte for byte, their estimates add up; 2 bake shards merge to the whole bake; 6 refusals"
