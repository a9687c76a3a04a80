#!/usr/bin/env bash
# Every bad input in DIR/*.json (and DIR/*.wif, weaving drafts) must give: exit status 1, the exact message in
# DIR/NAME.expect (as "clothbake: error: FILE: ..."), and no output (nor a
# temporary file beside it). The catalogue of other commands' bad inputs is
# bad_commands.sh.
#   bad_inputs.sh EXE DIR volume   -> clothbake volume INPUT -o OUT      (no OUT folder)
#   bad_inputs.sh EXE DIR render   -> clothbake render INPUT -o OUT.exr  (no OUT.exr)
# Files the inputs refer to (meshes) live in subfolders of DIR.
set -u
exe=$1 dir=$2 mode=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {  # name, input path, expected substring
  local name=$1 input=$2 expect=$3 out
  if [[ $mode == volume ]]; then
    out="$tmp/out_$name"
    "$exe" volume "$input" -o "$out" >"$tmp/stdout" 2>"$tmp/stderr"
  else
    mkdir -p "$tmp/out_$name"
    out="$tmp/out_$name/out.exr"
    "$exe" render "$input" -o "$out" >"$tmp/stdout" 2>"$tmp/stderr"
  fi
  local rc=$?
  local err
  err=$(cat "$tmp/stderr")
  if [[ $rc -ne 1 ]]; then
    echo "FAIL $name: exit status $rc, expected 1"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"clothbake: error: $input: "* ]]; then
    echo "FAIL $name: message does not name the file: $err"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"$expect"* ]]; then
    echo "FAIL $name: got      '$err'"; echo "             expected '$expect'"
    failures=$((failures + 1)); return
  fi
  if [[ -e $out ]]; then
    echo "FAIL $name: output $out was written"; failures=$((failures + 1)); return
  fi
  local left
  left=$(ls -A "$(dirname "$out")" | grep -v -e '^out_' -e '^stdout$' -e '^stderr$')
  if [[ -n $left ]]; then
    echo "FAIL $name: left behind: $left"; failures=$((failures + 1)); return
  fi
  echo "ok   $name: $err"
}
n=0
shopt -s nullglob
for input in "$dir"/*.json "$dir"/*.wif; do
  name=$(basename "$input"); name=${name%.*}
  check "$name" "$input" "$(cat "$dir/$name.expect")"
  n=$((n + 1))
done
check missing_file "$tmp/does_not_exist.json" "cannot open file (missing or unreadable)"
n=$((n + 1))
echo "$((n - failures)) of $n bad inputs refused correctly"
[[ $failures -eq 0 ]]
