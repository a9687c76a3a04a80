#!/usr/bin/env bash
# Where the march's time goes, route by route: perf (Debian's linux-perf,
# the cpu-clock software event, frame-pointer call graphs) over
#  1. the reference renderer: the paper scene at 16 spp on one thread;
#  2. the material bake of the paper cloth at the defaults (light fields,
#     node marches, factorisation), on every core;
#  3. lookup-render of the paper scene from that material at 4 spp.
# Each route's flat profile (self time by function, functions above 0.5 %)
# goes to OUT/ROUTE.txt; buckets.py sums it into the table of
# docs/design/performance.md, "Where the time goes".
# EXE is best built with frame pointers and symbols:
#   cmake -S . -B build-prof -G Ninja -DCMAKE_BUILD_TYPE=Release \
#     "-DCMAKE_CXX_FLAGS=-g -fno-omit-frame-pointer" -DCLOTHBAKE_BUILD_BENCHMARKS=OFF
#   cmake --build build-prof --target clothbake
# About 3 minutes on 2 cores.
#   profile.sh EXE OUT
set -euo pipefail
exe=$(realpath "$1") out=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
paper=$root/testscenes/paper/scene.json
mkdir -p "$out"
command -v perf >/dev/null || { echo "profile.sh: perf not found (apt-get install linux-perf)" >&2; exit 1; }
record() { # record ROUTE CMD...
  local route=$1
  shift
  perf record -q -e cpu-clock --call-graph fp -o "$out/$route.data" "$@" >"$out/$route.log" 2>&1
  perf report -q -i "$out/$route.data" --no-children --sort symbol --percent-limit 0.5 \
    -g none 2>/dev/null | sed 's/ \+$//' >"$out/$route.txt"
  echo "$route: $(wc -l <"$out/$route.txt") functions above 0.5 %" >&2
}
record render "$exe" render "$paper" -o "$out/render.exr" --spp 16 --threads 1 --quiet --stats
rm -rf "$out/material"
record material "$exe" material "$paper" -o "$out/material" --quiet
record lookup "$exe" lookup-render "$paper" "$out/material" -o "$out/lookup.exr" --spp 4 --quiet
/usr/bin/python3 "$here/buckets.py" "$out"
