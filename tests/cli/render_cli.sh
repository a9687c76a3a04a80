#!/usr/bin/env bash
# `clothbake render` writes an .exr output only. (Its bytes for 1 and 2 threads
# and across runs: determinism.sh, ctest cli.deterministic.)
set -u
exe=$1 scene=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
"$exe" render "$scene" -o "$tmp/out.png" --quiet 2>"$tmp/err" && fail "accepted a .png as the EXR output"
grep -q -- "-o: the output must be an .exr file" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[[ ! -e $tmp/out.png ]] || fail "wrote out.png"
echo "ok: a .png given as the EXR output is refused"
