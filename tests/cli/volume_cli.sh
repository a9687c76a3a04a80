#!/usr/bin/env bash
# `clothbake volume` gives the same volume (cells hash) and the same preview
# bytes with 1 and 2 threads, and writes every promised file.
set -eu
exe=$1
spec=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$exe" volume "$spec" -o "$tmp/a" --threads 1 >/dev/null
"$exe" volume "$spec" -o "$tmp/b" --threads 2 >/dev/null
for f in volume.vdb top.png tangents.png section_warp.png section_weft.png volume.json; do
  [[ -s $tmp/a/$f ]] || { echo "FAIL: $f missing or empty"; exit 1; }
done
for f in top.png tangents.png section_warp.png section_weft.png; do
  cmp "$tmp/a/$f" "$tmp/b/$f" || { echo "FAIL: $f differs between 1 and 2 threads"; exit 1; }
done
ha=$(grep -o '"cells_hash": "[0-9a-f]*"' "$tmp/a/volume.json")
hb=$(grep -o '"cells_hash": "[0-9a-f]*"' "$tmp/b/volume.json")
[[ -n $ha && $ha == "$hb" ]] || { echo "FAIL: cells hash differs: $ha vs $hb"; exit 1; }
# No temporary files left behind.
if ls -A "$tmp/a" | grep -q '^\.'; then echo "FAIL: temporary file left"; ls -A "$tmp/a"; exit 1; fi
echo "ok: same cells ($ha) and previews for 1 and 2 threads"
