#!/usr/bin/env bash
# `clothbake material`'s memory refusals lead to a bake: each case is refused
# (exit 1, "--memory-gib: ... holds N MiB before its table grows ..."), its
# message names a setting that fits and what it costs ("Fits: --address
# crossings --texels N: B blocks, the bake holds about M MiB, about D MB on
# disk, about T s here"), and the same command with those flags bakes, under the same
# budget, and holds the address and texels named. A real WIF (wi_32twill,
# 62 x 62 threads) at small settings:
# - addressed per crossing at 32 texels, asked, with 300 MiB left beside the
#   program (it holds 612 MiB);
# - 8 texels asked, the address left to the bake (per crossing: 0.13 texels
#   a thread over the whole repeat) with 38 MiB left (it holds 46 MiB);
# - nothing asked: at 38 MiB the bake takes 4 texels a crossing itself, at
#   15 MiB it is refused (4 holds 18 MiB) and the advice is 2.
#   material_advice.sh EXE ROOT
set -u
exe=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# shellcheck source=../lib/small_twill.sh
. "$root/tests/lib/small_twill.sh"
write_small_twill "$root" "$tmp/twill.json"
small=(--directions 4 --light-directions 4 --spp 1 --threads 2 --quiet)
case_n=0
follow() { # follow GIB ARGS...: refused, then baked with the advice
  local gib=$1
  shift
  case_n=$((case_n + 1))
  local out=$tmp/m$case_n
  if "$exe" material "$tmp/twill.json" -o "$out" "${small[@]}" --memory-gib "$gib" "$@" \
    >"$tmp/out" 2>"$tmp/err"; then
    fail "case $case_n ($*) was not refused in $gib GiB"
  fi
  [[ -e $out ]] && fail "case $case_n: the refusal wrote $out"
  grep -qE -- "--memory-gib: .* holds [0-9]+ MiB before its table grows" "$tmp/err" || fail "case $case_n: $(cat "$tmp/err")"
  local advice
  advice=$(grep -oE -- "Fits: --address crossings --texels [0-9]+: [0-9]+ blocks?, the bake holds about [0-9]+ MiB, about [0-9]+ MB on disk, about [0-9]+ (s|min) here" "$tmp/err") ||
    fail "case $case_n: no advice that names a setting: $(cat "$tmp/err")"
  local texels=${advice#*--texels }
  texels=${texels%%:*}
  echo "ok   case $case_n refused: $(cat "$tmp/err")"
  local kept=() skip=0 a  # the case's own --address and --texels give way to the advice's
  for a in "$@"; do
    if ((skip)); then skip=0; continue; fi
    case $a in --address | --texels) skip=1 ;; *) kept+=("$a") ;; esac
  done
  "$exe" material "$tmp/twill.json" -o "$out" "${small[@]}" --memory-gib "$gib" "${kept[@]}" \
    --address crossings --texels "$texels" >"$tmp/out" 2>"$tmp/err" ||
    fail "case $case_n: the advice followed was refused: $(cat "$tmp/err")"
  python3 -c "
import json, sys
m = json.load(open(sys.argv[1] + '/manifest.json'))
assert m['address'] == 'crossings' and m['texels'] == int(sys.argv[2]), (m['address'], m['texels'])" \
    "$out" "$texels" || fail "case $case_n: the material is not what the advice named"
  echo "ok   case $case_n: the advice followed ($advice) bakes"
}
# The budget counts the program and its input as read (the estimate's
# resident_bytes): the cases' budgets are that plus 300 and 38 MiB.
"$exe" material "$tmp/twill.json" -o "$tmp/est" "${small[@]}" --estimate >"$tmp/est.json" ||
  fail "the estimate"
base=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['resident_bytes'] / 2**30)" "$tmp/est.json")
gib() { python3 -c "import sys; print(f'{float(sys.argv[1]) + float(sys.argv[2]) / 1024:.4f}')" "$base" "$1"; }
follow "$(gib 300)" --address crossings --texels 32
follow "$(gib 38)" --texels 8
# Left to itself at 38 MiB, the bake takes 4 texels a crossing (18 MiB)
# rather than refuse 8, and says so; at 15 MiB neither fits, and the
# advice is 2 texels (11 MiB).
"$exe" material "$tmp/twill.json" -o "$tmp/auto" "${small[@]}" --memory-gib "$(gib 38)" \
  >"$tmp/out" 2>"$tmp/err" || fail "auto at 38 MiB was refused: $(cat "$tmp/err")"
python3 - "$tmp/auto" "$tmp/out" <<'PY' || fail "auto at 38 MiB"
import json, sys
m = json.load(open(sys.argv[1] + "/manifest.json"))
plan = json.loads(open(sys.argv[2]).read().strip().splitlines()[-1])["plan"]
assert (m["address"], m["texels"]) == ("crossings", 4), (m["address"], m["texels"])
assert "at 8 texels a crossing it would hold" in plan, plan
print("ok   auto at 38 MiB: " + plan)
PY
follow "$(gib 15)"
echo "material_advice: every refusal's advice bakes"
