#!/usr/bin/env bash
# The catalogue of bad inputs (docs/design/hardening.md, "Bad inputs"): every case in
# bad_commands/cases.txt runs one clothbake command and must give
#   1. exit status 1,
#   2. the exact message on stderr: its first line is "clothbake: error: " and
#      the case's expected text (a text ending in "..." is a prefix),
#   3. no output: the case's output folder $out stays empty (no result, no
#      temporary file) and no temporary file appears beside the inputs.
#   bad_commands.sh EXE ROOT [NAME...]     (names: run only those cases)
# A case line is "name | prepare | command | expected"; prepare and command are
# shell, run with these variables:
#   $exe   the clothbake binary          $in    tests/cli/bad_commands (inputs)
#   $root  the source tree               $case  a scratch folder for this case's inputs
#   $out   the case's output folder (must stay empty)
#   $bake  a small good bake of testscenes/slab (read only; copy it to change it)
#   $other a small good bake of another scene (slab, brighter light)
#   $material a small good cloth material of testscenes/slab
#   $slab  testscenes/slab/scene.json
# prepare may call the helpers below; exit status 77 from prepare skips the
# case with the reason it printed (only for what the machine cannot do).
set -u
exe=$1 root=$2
shift 2
only=("$@")
in=$root/tests/cli/bad_commands
slab=$root/testscenes/slab/scene.json
tmp=$(mktemp -d)
trap 'chmod -R u+rwX "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT

# --- helpers for prepare ---------------------------------------------------
# A copy of the good bake, at $case/bake.
bake_copy() { cp -r "$bake" "$case/bake"; }
# Edits $case/bake/manifest.json with a Python statement on `m`.
manifest_edit() {
  python3 - "$case/bake/manifest.json" "$1" <<'PY'
import json, sys
path, stmt = sys.argv[1], sys.argv[2]
m = json.load(open(path))
exec(stmt)
json.dump(m, open(path, "w"), indent=2)
PY
}
# Keeps the first N bytes of FILE.
truncate_to() { head -c "$2" "$1" >"$1.cut" && mv "$1.cut" "$1"; }
# Makes FILE unreadable for the command. Root reads anything: then the command
# runs without CAP_DAC_OVERRIDE / CAP_DAC_READ_SEARCH (setpriv, util-linux);
# where that is impossible the case is skipped with the reason.
run_as=()
unreadable() {
  chmod 000 "$1"
  if [[ $(id -u) -eq 0 ]]; then
    run_as=(setpriv --bounding-set=-dac_override,-dac_read_search --)
    if ! "${run_as[@]}" true 2>/dev/null || "${run_as[@]}" cat "$1" >/dev/null 2>&1; then
      echo "running as root and cannot drop CAP_DAC_OVERRIDE (setpriv): chmod 000 does not stop root"
      return 77
    fi
  fi
}

# --- the two good bakes every lookup case starts from ----------------------
bake=$tmp/good_bake
other=$tmp/other_bake
small=(--directions 3 --texels 4 --spp 1 --quiet)
"$exe" bake "$slab" -o "$bake" "${small[@]}" >/dev/null || { echo "FAIL: the good bake"; exit 1; }
mkdir -p "$tmp/other_scene"
cp "$root/testscenes/slab/quad.obj" "$root/testscenes/slab/cloth.json" "$tmp/other_scene/"
sed 's/"intensity": 1.0/"intensity": 2.0/' "$slab" >"$tmp/other_scene/scene.json"
"$exe" bake "$tmp/other_scene/scene.json" -o "$other" "${small[@]}" >/dev/null ||
  { echo "FAIL: the other bake"; exit 1; }
material=$tmp/good_material
"$exe" material "$slab" -o "$material" --texels 4 --directions 3 --light-directions 3 --spp 1 \
  --field-supersample 1 --quiet >/dev/null || { echo "FAIL: the good material"; exit 1; }
chmod -R a-w "$bake" "$other" "$material"  # cases must copy before changing (root ignores this)

# --- the cases -------------------------------------------------------------
failures=0 passed=0 skipped=0
trim() { local s=$1; s=${s#"${s%%[![:space:]]*}"}; printf '%s' "${s%"${s##*[![:space:]]}"}"; }
while IFS= read -r line || [[ -n $line ]]; do
  [[ -z ${line//[[:space:]]/} || $line == \#* ]] && continue
  IFS='|' read -r name prepare command expected <<<"$line"
  name=$(trim "$name") prepare=$(trim "$prepare") command=$(trim "$command")
  expected=$(trim "$expected")
  if [[ ${#only[@]} -gt 0 && " ${only[*]} " != *" $name "* ]]; then continue; fi
  case=$tmp/cases/$name
  out=$case/out
  mkdir -p "$case" "$out"
  run_as=()
  if [[ -n $prepare ]]; then
    reason=$(cd "$case" && eval "$prepare")
    rc=$?
    if [[ $rc -eq 77 ]]; then
      echo "skip $name: $reason"; skipped=$((skipped + 1)); continue
    elif [[ $rc -ne 0 ]]; then
      echo "FAIL $name: prepare failed ($rc): $reason"; failures=$((failures + 1)); continue
    fi
  fi
  # unreadable() sets run_as in a subshell above; set it here again for the run.
  if [[ $prepare == *unreadable* && $(id -u) -eq 0 ]]; then
    run_as=(setpriv --bounding-set=-dac_override,-dac_read_search --)
  fi
  eval "set -- $command"
  "${run_as[@]}" "$@" >"$case.stdout" 2>"$case.stderr"
  rc=$?
  want=$expected
  for var in case out other bake slab root in; do want=${want//"\$$var"/${!var}}; done
  want="clothbake: error: $want"
  got=$(head -1 "$case.stderr")
  if [[ $rc -ne 1 ]]; then
    echo "FAIL $name: exit status $rc, expected 1 ($got)"; failures=$((failures + 1)); continue
  fi
  if [[ $want == *... ]]; then
    match=0; [[ $got == "${want%...}"* ]] && match=1
  else
    match=0; [[ $got == "$want" ]] && match=1
  fi
  if [[ $match -ne 1 ]]; then
    echo "FAIL $name: got      '$got'"; echo "     expected '$want'"
    failures=$((failures + 1)); continue
  fi
  left=$(ls -A "$out")
  temps=$(find "$case" "$bake" "$other" -name '.*.tmp*' -o -name '*.tmp-*' -o -name '*.old-*' 2>/dev/null)
  if [[ -n $left || -n $temps ]]; then
    echo "FAIL $name: left behind: $left $temps"; failures=$((failures + 1)); continue
  fi
  echo "ok   $name: $got"
  passed=$((passed + 1))
done <"$in/cases.txt"
echo "$passed of $((passed + failures)) bad commands refused correctly ($skipped skipped)"
[[ $failures -eq 0 && $passed -gt 0 ]]
