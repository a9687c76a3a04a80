#!/usr/bin/env bash
# Every bad scene in DIR/*.json must give: exit status 1, the exact message in
# DIR/NAME.expect (as "clothbake: error: FILE: ..."), and no output image.
# Meshes the scenes refer to live in DIR/meshes/.
set -u
exe=$1
dir=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {  # name, scene path, expected substring
  local name=$1 scene=$2 expect=$3
  local out="$tmp/out_$name"
  mkdir -p "$out"
  "$exe" render "$scene" -o "$out/out.exr" >"$tmp/stdout" 2>"$tmp/stderr"
  local rc=$?
  local err
  err=$(cat "$tmp/stderr")
  if [[ $rc -ne 1 ]]; then
    echo "FAIL $name: exit status $rc, expected 1"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"clothbake: error: $scene: "* ]]; then
    echo "FAIL $name: message does not name the file: $err"; failures=$((failures + 1)); return
  fi
  if [[ $err != *"$expect"* ]]; then
    echo "FAIL $name: got      '$err'"; echo "             expected '$expect'"
    failures=$((failures + 1)); return
  fi
  if [[ -e $out/out.exr ]]; then
    echo "FAIL $name: out.exr was written"; failures=$((failures + 1)); return
  fi
  echo "ok   $name: $err"
}
n=0
for scene in "$dir"/*.json; do
  name=$(basename "$scene" .json)
  check "$name" "$scene" "$(cat "$dir/$name.expect")"
  n=$((n + 1))
done
check missing_file "$tmp/does_not_exist.json" "cannot open file (missing or unreadable)"
n=$((n + 1))
echo "$((n - failures)) of $n bad scenes refused correctly"
[[ $failures -eq 0 ]]
