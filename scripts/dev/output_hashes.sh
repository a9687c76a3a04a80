#!/usr/bin/env bash
# The bytes of every output kind on the paper and slab scenes, as sha256
# prefixes, for a refactoring that must change none of them (issue 14):
#   scripts/dev/output_hashes.sh CLOTHBAKE [OUT_TSV]
# Runs render, bake (full and adaptive; every file of the folder, the
# manifest without its timings), lookup-render and volume (the cells hash:
# OpenVDB writes a random UUID into each file, docs/hardening.md). One
# thread and two threads must agree too. About 2 minutes on 2 cores.
set -euo pipefail
exe=$(realpath "$1")
out=${2:-/dev/stdout}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
h() { sha256sum "$1" | cut -c1-16; }
# A bake folder's bytes: its EXRs, and the manifest less the statistics
# (seconds differ from run to run).
hbake() {
  local d=$1 acc=""
  for f in "$d"/*.exr; do acc+="$(basename "$f"):$(h "$f") "; done
  acc+="manifest:$(/usr/bin/python3 -c "
import json, sys, hashlib
m = json.load(open('$d/manifest.json')); m.pop('statistics', None)
print(hashlib.sha256(json.dumps(m, sort_keys=True).encode()).hexdigest()[:16])")"
  echo "$acc" | sha256sum | cut -c1-16
}
{
printf "output\tscene\tthreads\thash\n"
for scene in paper slab; do
  s=$root/testscenes/$scene/scene.json
  for t in 1 2; do
    "$exe" render "$s" -o "$tmp/r.exr" --spp 2 --threads $t --quiet
    printf "render (2 spp)\t%s\t%s\t%s\n" $scene $t "$(h "$tmp/r.exr")"
  done
  "$exe" bake "$s" -o "$tmp/full" --directions 4 --texels 8 --spp 1 --threads 2 --quiet >/dev/null
  printf "bake full (K 4, R 8)\t%s\t2\t%s\n" $scene "$(hbake "$tmp/full")"
  "$exe" bake "$s" -o "$tmp/adaptive" --adaptive --directions 8 --spp 1 --threads 2 --quiet >/dev/null
  printf "bake adaptive (K 8)\t%s\t2\t%s\n" $scene "$(hbake "$tmp/adaptive")"
  "$exe" lookup-render "$s" "$tmp/adaptive" -o "$tmp/l.exr" --spp 4 --threads 2 --quiet
  printf "lookup-render (4 spp)\t%s\t2\t%s\n" $scene "$(h "$tmp/l.exr")"
  "$exe" volume "$(dirname "$s")/cloth.json" -o "$tmp/vol" --quiet >/dev/null 2>&1 || \
    "$exe" volume "$(dirname "$s")/cloth.json" -o "$tmp/vol" >/dev/null
  cells=$(ls "$tmp/vol" | tr '\n' ' ')
  acc=""
  for f in "$tmp"/vol/*; do
    case $f in
      *.vdb) ;;
      *.json) acc+="$(basename "$f"):$(/usr/bin/python3 -c "
import json, hashlib
m = json.load(open('$f')); m.pop('generate_seconds', None)
print(hashlib.sha256(json.dumps(m, sort_keys=True).encode()).hexdigest()[:16])") ";;
      *) acc+="$(basename "$f"):$(h "$f") ";;
    esac
  done
  printf "volume (PNGs, volume.json less its seconds; the VDB's cells hash is in it)\t%s\t-\t%s\n" $scene "$(echo "$acc" | sha256sum | cut -c1-16)"
  rm -rf "$tmp/full" "$tmp/adaptive" "$tmp/vol"
done
} >"$out"
