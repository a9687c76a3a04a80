#!/usr/bin/env bash
# Cycles with clothbake's bake against Cycles rendering the same cloth as a
# real volume, at matched noise (docs/design/performance.md, "Cycles: baked lookup
# against a real volume"). Scene: testscenes/flat (a flat cloth of 6 x 6
# repeats, isotropic shading, so both routes compute the same physics).
#
#   lab/cycles_timing/cycles_volume_timing.sh [--reuse-bake]
#
# Needs the built clothbake (build/baker/clothbake, or $CLOTHBAKE), Blender 3.4
# ($BLENDER, default blender), /usr/bin/python3 with OpenImageIO, numpy,
# pyopenvdb, matplotlib and PIL, and blender_addon/headless_render.py. Installs
# nothing. Writes under out/flat/ and the figure docs/images/flat_cycles_compare.png.
# 4.6 minutes on the idle 2-core machine (the bake 68 s, the volume renders
# 2.9 min); run it on an otherwise idle machine, the seconds are the point
# (steps.tsv records the load average around every step). --reuse-bake keeps
# an existing out/flat/bake (its bake_seconds are still reported from its
# manifest, and its step line from the previous steps.tsv).
#
# Sample counts: VOL_SAMPLES (1,4,16,64,256) against a VOL_REF-sample
# reference (512, another seed); BAKE_SAMPLES (1,4,16) against BAKE_REF (256);
# MAT_SAMPLES (4,16,64) against MAT_REF (256) for the cloth material.
set -euo pipefail

cd "$(dirname "$0")/../.."
CLOTHBAKE=${CLOTHBAKE:-build/baker/clothbake}
BLENDER=${BLENDER:-blender}
PY=/usr/bin/python3
SCENE=testscenes/flat/scene.json
OUT=out/flat
FIGURE=docs/images/flat_cycles_compare.png
VOL_SAMPLES=${VOL_SAMPLES:-1,4,16,64,256}
VOL_REF=${VOL_REF:-512}
BAKE_SAMPLES=${BAKE_SAMPLES:-1,4,16}
BAKE_REF=${BAKE_REF:-256}
MAT_SAMPLES=${MAT_SAMPLES:-4,16,64}
MAT_REF=${MAT_REF:-256}
REUSE_BAKE=0
for a in "$@"; do
  case "$a" in
    --reuse-bake) REUSE_BAKE=1 ;;
    *) echo "usage: $0 [--reuse-bake]" >&2; exit 2 ;;
  esac
done
[[ -x $CLOTHBAKE ]] || { echo "no clothbake at $CLOTHBAKE (build first)" >&2; exit 1; }
[[ -f blender_addon/headless_render.py ]] || { echo "no blender_addon/headless_render.py" >&2; exit 1; }

mkdir -p "$OUT/vol" "$OUT/bakeroute" "$OUT/matroute"
old_bake_step=$(grep -s '^clothbake_bake' "$OUT/steps.tsv" || true)
: > "$OUT/steps.tsv"
TIMES_TMP=$(mktemp)
# CPU_NOW := CPU seconds (user + system) of this shell's finished children so
# far. Not through $(...) or a pipe: a subshell has no children of its own.
children_cpu() {
  times > "$TIMES_TMP"
  CPU_NOW=$(tail -1 "$TIMES_TMP" | awk '{ n = split($0, f, " "); s = 0
    for (i = 1; i <= n; i++) { split(f[i], p, "m"); s += p[1] * 60 + substr(p[2], 1, length(p[2]) - 1) }
    print s }')
}
# Runs a step, appending "name start end load1_before load1_after cpu_seconds"
# to steps.tsv (load1: the 1-minute load average, to show other work on the machine).
step() {
  local name=$1; shift
  local l0 t0 t1 l1 c0 cpu
  l0=$(cut -d' ' -f1 /proc/loadavg); t0=$(date +%s.%N); children_cpu; c0=$CPU_NOW
  "$@"
  t1=$(date +%s.%N); l1=$(cut -d' ' -f1 /proc/loadavg); children_cpu
  cpu=$(echo "$CPU_NOW - $c0" | bc)
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$t0" "$t1" "$l0" "$l1" "$cpu" >> "$OUT/steps.tsv"
  echo "== $name: $(echo "$t1 - $t0" | bc) s wall, $cpu s CPU (load $l0 -> $l1)"
}
blender_run() {  # blender_run SCRIPT... -- ARGS (quiet unless it fails)
  local log; log=$(mktemp)
  if ! "$BLENDER" -b --factory-startup --python-exit-code 1 "$@" > "$log" 2>&1; then
    cat "$log" >&2; rm -f "$log"; return 1
  fi
  grep -E '^(volume_render|light_units):' "$log" || true
  rm -f "$log"
}
export BLENDER_USER_SCRIPTS BLENDER_USER_CONFIG
BLENDER_USER_SCRIPTS=$(mktemp -d); BLENDER_USER_CONFIG=$BLENDER_USER_SCRIPTS
trap 'rm -rf "$BLENDER_USER_SCRIPTS" "$TIMES_TMP"' EXIT

# 1. Blender's light units, measured on a white diffuse plane.
step light_units blender_run -P lab/light_units/light_units.py -- "$OUT/light_units.json"

# 2. The volume texture (one repeat) and its tiling over the cloth.
step clothbake_volume "$CLOTHBAKE" volume "$SCENE" -o "$OUT/volume"
step tile_volume "$PY" lab/common/tile_volume.py "$SCENE" "$OUT/volume" "$OUT/tiled.vdb"

# 3. clothbake's own renderer at 16 spp (for how far the two Cycles pictures are from it).
step clothbake_render "$CLOTHBAKE" render "$SCENE" -o "$OUT/clothbake_render.exr" \
  --png "$OUT/clothbake_render.png" --spp 16 2> /dev/null

# 4. The bake (adaptive to the scene's camera).
if [[ $REUSE_BAKE == 1 && -f $OUT/bake/manifest.json ]]; then
  echo "== clothbake_bake: reusing $OUT/bake"
  [[ -n $old_bake_step ]] && printf '%s\n' "$old_bake_step" >> "$OUT/steps.tsv"
else
  step clothbake_bake "$CLOTHBAKE" bake "$SCENE" -o "$OUT/bake" --adaptive --quiet
fi

# clothbake's own drawing from the bake (what the add-on should reproduce);
# for the comparison of pictures only, so a failure is reported, not fatal.
rm -f "$OUT/lookup_render.exr"
step clothbake_lookup_render "$CLOTHBAKE" lookup-render "$SCENE" "$OUT/bake" -o "$OUT/lookup_render.exr" \
  || echo "warning: clothbake lookup-render failed; the report leaves it out" >&2

# 5. The real-volume route: test renders in one Blender session, the
#    reference (another seed) in another; one grid-colour render for its cost.
step volume_renders blender_run -P lab/common/volume_render.py -- "$SCENE" "$OUT/volume" \
  "$OUT/tiled.vdb" "$OUT/light_units.json" "$OUT/vol" --samples "$VOL_SAMPLES" --seed 1
step volume_reference blender_run -P lab/common/volume_render.py -- "$SCENE" "$OUT/volume" \
  "$OUT/tiled.vdb" "$OUT/light_units.json" "$OUT/vol" --samples "$VOL_REF" --seed 7
step volume_grid blender_run -P lab/common/volume_render.py -- "$SCENE" "$OUT/volume" \
  "$OUT/tiled.vdb" "$OUT/light_units.json" "$OUT/vol" --samples 16 --seed 1 --color grid --tag volume_grid

# 6. The bake route: the add-on's headless render, one session per sample count.
bake_render() {  # bake_render SAMPLES SEED
  local tag="bake_s$1_seed$2"
  CLOTHBAKE_RENDER_CLOCK="$OUT/bakeroute/${tag}_clock.json" step "$tag" blender_run \
    -P lab/cycles_timing/render_clock.py -P blender_addon/headless_render.py -- \
    "$SCENE" "$OUT/bake" "$OUT/bakeroute/$tag.exr" --samples "$1" --seed "$2" \
    --timings "$OUT/bakeroute/${tag}_timings.json"
}
for n in ${BAKE_SAMPLES//,/ }; do bake_render "$n" 1; done
bake_render "$BAKE_REF" 7

# 7. The material route (issue 16): one cloth material of the flat cloth,
#    baked once for any scene, applied by the add-on (exact route).
if [[ $REUSE_BAKE == 1 && -f $OUT/material/manifest.json ]]; then
  echo "== clothbake_material: reusing $OUT/material"
else
  step clothbake_material "$CLOTHBAKE" material "$SCENE" -o "$OUT/material" --parts rgb --quiet
fi
material_render() {  # material_render SAMPLES SEED
  local tag="material_s$1_seed$2"
  CLOTHBAKE_RENDER_CLOCK="$OUT/matroute/${tag}_clock.json" step "$tag" blender_run \
    -P lab/cycles_timing/render_clock.py -P blender_addon/headless_render.py -- \
    "$SCENE" "$OUT/material" "$OUT/matroute/$tag.exr" --samples "$1" --seed "$2" \
    --timings "$OUT/matroute/${tag}_timings.json"
}
for n in ${MAT_SAMPLES//,/ }; do material_render "$n" 1; done
material_render "$MAT_REF" 7

# 8. Figures.
"$PY" lab/cycles_timing/cycles_timing_report.py "$OUT" "$VOL_SAMPLES" "$VOL_REF" "$BAKE_SAMPLES" "$BAKE_REF" "$FIGURE" \
  "$MAT_SAMPLES" "$MAT_REF"
