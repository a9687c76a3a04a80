#!/usr/bin/env bash
# `clothbake render` writes the same EXR and PNG bytes for 1 and 2 threads and
# across runs, and an .exr output only.
set -u
exe=$1 scene=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
"$exe" render "$scene" -o "$tmp/a.exr" --png "$tmp/a.png" --threads 1 --quiet || fail "render 1 thread"
"$exe" render "$scene" -o "$tmp/b.exr" --png "$tmp/b.png" --threads 2 --quiet || fail "render 2 threads"
"$exe" render "$scene" -o "$tmp/c.exr" --threads 2 --quiet || fail "second run"
cmp "$tmp/a.exr" "$tmp/b.exr" || fail "EXR differs between 1 and 2 threads"
cmp "$tmp/a.png" "$tmp/b.png" || fail "PNG differs between 1 and 2 threads"
cmp "$tmp/b.exr" "$tmp/c.exr" || fail "EXR differs between two runs"
"$exe" render "$scene" -o "$tmp/out.png" --quiet 2>"$tmp/err" && fail "accepted a .png as the EXR output"
grep -q -- "-o: the output must be an .exr file" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[[ ! -e $tmp/out.png ]] || fail "wrote out.png"
echo "ok: identical bytes for 1 and 2 threads and across runs"
