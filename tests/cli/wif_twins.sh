#!/usr/bin/env bash
# A treadled draft and its liftplan twin, both written by the weaving program
# itself (testscenes/wif/real/PROVENANCE.md), must give identical cells: the
# same cells_hash from `clothbake volume`. A spec key that changes the weave
# (the first pick of the twin lifted differently) must change the hash, so
# the comparison can fail.
#   wif_twins.sh CLOTHBAKE REPO_ROOT
set -euo pipefail
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
real=$root/testscenes/wif/real
hash_of() {  # spec json text -> cells_hash
  local name=$1 text=$2
  printf '%s\n' "$text" >"$tmp/$name.json"
  "$exe" volume "$tmp/$name.json" -o "$tmp/$name" >/dev/null
  /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['cells_hash'])" "$tmp/$name/volume.json"
}
small='"resolution": {"cells_per_thread": 2, "layers": 6, "supersample": 1}'
fail=0
for pair in "tw_honeysuckle tw_honeysuckle_lp" "wi_641_single wi_641_liftplan"; do
  read -r a b <<<"$pair"
  ha=$(hash_of "$a" "{\"weave\": {\"wif\": \"$real/$a.wif\"}, $small}")
  hb=$(hash_of "$b" "{\"weave\": {\"wif\": \"$real/$b.wif\"}, $small}")
  if [[ $ha == "$hb" ]]; then echo "ok   $a (treadled) = $b (liftplan): cells_hash $ha"
  else echo "FAIL $a $ha != $b $hb"; fail=1; fi
done
# The negative: the same twin with a different weft colour hashes differently.
hc=$(hash_of recoloured "{\"weave\": {\"wif\": \"$real/tw_honeysuckle_lp.wif\"}, \"weft\": {\"color\": [0.5, 0.5, 0.5]}, $small}")
if [[ $hc == "$(hash_of again "{\"weave\": {\"wif\": \"$real/tw_honeysuckle.wif\"}, $small}")" ]]; then
  echo "FAIL the hash does not see a changed colour"; fail=1
else echo "ok   a recoloured twin hashes differently ($hc)"; fi
exit $fail
