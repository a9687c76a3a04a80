#!/usr/bin/env bash
# The light-term limits of Apply material's SVM note, measured again
# (blender_addon/clothbake/core/svm_budget.py, docs/design/material.md "Lights and
# the SVM stack"):
#   lab/svm_limits/svm_limits.sh CLOTHBAKE [WORK_DIR]
# Bakes the paper cloth twice (colour-free and RGB; R 16, K 12, KL 8, 1
# sample, as the table was measured), makes the paper scene with its lights
# replaced by N point lights on a ring, and for each (parts, route) of
# LIGHT_TERM_LIMIT renders N = limit (must compile) and N = limit + 1 (must
# overflow), N counting the lights' terms (limit less the route's world
# terms, svm_budget.WORLD_TERMS) through scripts/dev/svm_peak.sh. Prints every peak; exits 1 when
# a limit in the table is not the edge this Blender shows. About 30 minutes
# on 2 cores (each render builds and compiles a 6000-node shader).
set -euo pipefail
exe=$(realpath "$1")
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=${2:-$(mktemp -d "${TMPDIR:-/tmp}/svm_limits.XXXXXX")}
mkdir -p "$work"
for parts in specular-warp-weft rgb; do
  [ -f "$work/$parts/manifest.json" ] ||
    "$exe" material "$root/testscenes/paper/scene.json" -o "$work/$parts" --parts "$parts" \
      --texels 16 --directions 12 --light-directions 8 --spp 1 --quiet >/dev/null
done
# The table, and the scenes its edges need.
limits=$(cd "$root/blender_addon" && /usr/bin/python3 -c '
from clothbake.core.svm_budget import LIGHT_TERM_LIMIT, WORLD_TERMS
for (cf, route), n in sorted(LIGHT_TERM_LIMIT.items()):
    print("specular-warp-weft" if cf else "rgb", route, n - WORLD_TERMS[route])')
/usr/bin/python3 - "$root" "$work" $(echo "$limits" | awk '{print $3, $3 + 1}') <<'EOF'
import json, math, sys
root, work, counts = sys.argv[1], sys.argv[2], sorted(set(map(int, sys.argv[3:])))
src = json.load(open(f"{root}/testscenes/paper/scene.json"))
for n in counts:
    scene = json.loads(json.dumps(src))
    scene["lights"] = [{"type": "point", "color": [1, 1, 1], "intensity": 8.0 / n,
                        "position": [2.5 * math.cos(2 * math.pi * i / n),
                                     2.5 * math.sin(2 * math.pi * i / n), 2.4]}
                       for i in range(n)]
    for key in ("mesh", "cloth"):
        scene["objects"][0][key] = f"{root}/testscenes/paper/{scene['objects'][0][key]}"
    json.dump(scene, open(f"{work}/points{n}.json", "w"), indent=1)
EOF
wrong=0
while read -r parts route limit; do
  for n in "$limit" $((limit + 1)); do
    if out=$(bash "$root/scripts/dev/svm_peak.sh" "$work/points$n.json" "$work/$parts" "$route" 2>&1); then
      got=ok; else got=overflow; fi
    want=$([ "$n" -le "$limit" ] && echo ok || echo overflow)
    peak=$(echo "$out" | awk '/peak/ {print $(NF - 2)}' | head -1)
    echo "$parts $route: $n point lights: $got (peak ${peak:-?} of 255; the table says $want)"
    [ "$got" = "$want" ] || wrong=1
  done
done <<<"$limits"
[ "$wrong" = 0 ] || { echo "svm_limits.sh: LIGHT_TERM_LIMIT is not the edge this Blender shows" >&2; exit 1; }
echo "svm_limits.sh: every limit is the edge"
