#!/usr/bin/env bash
# `clothbake bake --estimate`: one JSON object with the plan and a timed
# estimate, exit 0, and no output folder; its plan figures are the real
# bake's (full and adaptive); an existing lookup folder is left as it was;
# what a bake would refuse, the estimate refuses too. No timing is compared:
# the seconds only have to be positive.
set -u
exe=$1 root=$2
paper=$root/testscenes/paper/scene.json
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# estimate NAME ARGS...: --estimate into $tmp/NAME.json, which must be valid
# and complete, and must leave no $tmp/NAME* folder behind.
estimate() {
  local name=$1; shift
  "$exe" bake "$paper" -o "$tmp/$name" --estimate "$@" >"$tmp/$name.json" 2>"$tmp/$name.err" \
    || fail "--estimate $* exited $?: $(cat "$tmp/$name.err")"
  /usr/bin/python3 - "$tmp/$name.json" <<'PY' || fail "--estimate $*: JSON check"
import json, sys
d = json.load(open(sys.argv[1]))
keys = ("march_samples", "full_march_samples", "direction_tiles", "texels", "bytes_uncompressed",
        "seconds_estimated", "probe_samples", "probe_seconds", "threads", "adaptive")
for key in keys:
    assert key in d, f"missing {key}"
assert isinstance(d["adaptive"], bool)
assert d["seconds_estimated"] > 0 and d["probe_seconds"] > 0, d
assert 0 < d["probe_samples"] <= d["march_samples"] <= d["full_march_samples"], d
assert d["threads"] >= 1
PY
  compgen -G "$tmp/$name*" | grep -v "\.json$\|\.err$" && fail "--estimate $* left output behind"
  echo "ok: --estimate $*: $(tr -d ' \n' <"$tmp/$name.json")"
}

# same KEY A.json B.json: the key's value is the same in both.
same() {
  /usr/bin/python3 -c "import json,sys; a,b=(json.load(open(f))['$1'] for f in sys.argv[1:]); assert a==b, (a,b)" \
    "$2" "$3" || fail "$1 differs between $2 and $3"
}

small=(--directions 3 --texels 4 --spp 2 --quiet)
estimate full "${small[@]}"
"$exe" bake "$paper" -o "$tmp/full_bake" "${small[@]}" >"$tmp/full_bake.json" || fail "full bake"
adaptive=(--adaptive --directions 3 --texels-per-pixel 0.25 --spp 1 --quiet)
estimate adaptive "${adaptive[@]}"
"$exe" bake "$paper" -o "$tmp/adaptive_bake" "${adaptive[@]}" >"$tmp/adaptive_bake.json" \
  || fail "adaptive bake"
for kind in full adaptive; do
  for key in march_samples full_march_samples direction_tiles texels bytes_uncompressed; do
    same $key "$tmp/$kind.json" "$tmp/${kind}_bake.json"
  done
done
/usr/bin/python3 -c "import json; assert json.load(open('$tmp/adaptive.json'))['adaptive'] is True" \
  || fail "adaptive: false"
echo "ok: the plan figures of both estimates are the real bakes'"

# --threads is the probe's thread count too.
estimate one_thread "${small[@]}" --threads 1
/usr/bin/python3 -c "import json; assert json.load(open('$tmp/one_thread.json'))['threads'] == 1" \
  || fail "--threads 1 not reported"

# Onto an existing lookup folder: the folder is left as it was.
before=$(cd "$tmp/full_bake" && sha256sum ./*)
"$exe" bake "$paper" -o "$tmp/full_bake" --estimate "${small[@]}" >/dev/null || fail "estimate over a bake"
[[ $(cd "$tmp/full_bake" && sha256sum ./*) == "$before" ]] || fail "--estimate changed the bake"
compgen -G "$tmp/full_bake.*-*" && fail "--estimate left a temporary folder"
echo "ok: an existing bake is left as it was"

# What a bake refuses in step 1, the estimate refuses, with no output.
"$exe" bake "$paper" -o "$tmp/huge" --estimate --directions 64 --texels 4096 --quiet \
  >"$tmp/huge.out" 2>"$tmp/huge.err" && fail "--estimate of a bake over the memory budget succeeded"
grep -qF -- "--texels: the lookup would need" "$tmp/huge.err" || fail "huge: $(cat "$tmp/huge.err")"
[[ ! -s $tmp/huge.out && ! -e $tmp/huge ]] || fail "huge: output"
echo "ok: refused: $(head -1 "$tmp/huge.err")"
