#!/usr/bin/env bash
# Every bad spec in DIR/*.json must give: exit status 1, the exact message in
# DIR/NAME.expect (as "clothbake: error: FILE: ..."), and no output folder.
set -u
exe=$1
dir=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {  # name, spec path, expected substring
  local name=$1 spec=$2 expect=$3
  local out="$tmp/out_$name"
  "$exe" volume "$spec" -o "$out" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  local err
  err=$(cat "$tmp/stderr")
  if [[ $rc -ne 1 ]]; then
    echo "FAIL $name: exit status $rc, expected 1"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"clothbake: error: $spec: "* ]]; then
    echo "FAIL $name: message does not name the file: $err"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"$expect"* ]]; then
    echo "FAIL $name: got      '$err'"; echo "             expected '$expect'"
    failures=$((failures + 1)); return
  fi
  if [[ -e $out ]]; then
    echo "FAIL $name: output folder was created"; failures=$((failures + 1)); return
  fi
  echo "ok   $name: $err"
}
n=0
for spec in "$dir"/*.json; do
  name=$(basename "$spec" .json)
  check "$name" "$spec" "$(cat "$dir/$name.expect")"
  n=$((n + 1))
done
check missing_file "$tmp/does_not_exist.json" "cannot open file (missing or unreadable)"
n=$((n + 1))
echo "$((n - failures)) of $n bad specs refused correctly"
[[ $failures -eq 0 ]]
