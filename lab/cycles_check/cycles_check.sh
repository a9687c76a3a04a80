#!/usr/bin/env bash
# The independent check (issue 6): clothbake's reference renderer in its
# isotropic mode against Blender 3.4 Cycles rendering the same cloth as a real
# volume (OpenVDB) with volume_bounces = 0, an isotropic phase, and the same
# camera, lights and pixel filter (docs/design/results.md, "An independent check:
# Cycles real volumes").
#
#   lab/cycles_check/cycles_check.sh [OUT_DIR] [--check] [--figures DIR]
#
# Scenes: testscenes/slab/cycles_check.json (the uniform slab against a grey
# background, so that both its scattering and its see-through count) and
# testscenes/flat/cycles_check.json (the woven cloth, 6 x 6 repeats tiled into
# one VDB, seen 50 to 69 degrees from its normal, the frame inside the cloth).
# For each: `clothbake volume` + lab/common/tile_volume.py (the VDB), `clothbake
# render` (the reference, CB_SPP samples), lab/common/volume_render.py
# (Cycles at CY_SPP samples with two seeds; their mean is the Cycles picture,
# their difference its noise), lab/cycles_check/cycles_check_report.py (`clothbake
# compare --json`, mean ratio over the cloth, the comparison PNG).
#
# Light units are not measured here but given by the law issue 5 measured
# (lab/light_units/light_units.py): a Sun of strength S gives irradiance S;
# a Point light of P watts gives P / (4 pi) at 1 unit, so clothbake's point
# intensity I is P = 4 pi I watts. A wrong conversion therefore fails the check.
#
# --check applies the bounds given in the environment (SLAB_MIN_PSNR,
# SLAB_MIN_PSNR4 (after 4 x 4 box averaging), SLAB_RATIO ("LO,HI"), and the
# same for FLAT_; tests/blender/cycles_check.sh sets them) and exits 1 if any fails. --figures DIR writes the comparison
# PNGs there (DIR/cycles_check_slab.png, DIR/cycles_check_flat.png).
# Environment: CLOTHBAKE (default build/baker/clothbake), BLENDER (blender),
# SLAB_CY_SPP (512), FLAT_CY_SPP (128), SLAB_CB_SPP (64), FLAT_CB_SPP (16),
# SCENES ("slab flat"), REUSE (1: keep OUT_DIR's volumes and clothbake
# renders from an earlier run, render Cycles only), CY_ARGS (extra volume_render.py options, e.g.
# "--voxel-shift 1.5" for experiments).
# About 1.5 minutes on the idle 2-core machine.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CLOTHBAKE=${CLOTHBAKE:-$ROOT/build/baker/clothbake}
BLENDER=${BLENDER:-blender}
PY=/usr/bin/python3
SLAB_CY_SPP=${SLAB_CY_SPP:-512}
FLAT_CY_SPP=${FLAT_CY_SPP:-128}
SLAB_CB_SPP=${SLAB_CB_SPP:-64}
FLAT_CB_SPP=${FLAT_CB_SPP:-16}
SCENES=${SCENES:-slab flat}
CY_ARGS=${CY_ARGS:-}
OUT=$ROOT/out/cycles_check
CHECK=0
FIGURES=
while [[ $# -gt 0 ]]; do
  case "$1" in
    --check) CHECK=1; shift ;;
    --figures) FIGURES=$2; shift 2 ;;
    -*) echo "usage: $0 [OUT_DIR] [--check] [--figures DIR]" >&2; exit 2 ;;
    *) OUT=$1; shift ;;
  esac
done
[[ -x $CLOTHBAKE ]] || { echo "no clothbake at $CLOTHBAKE (build first)" >&2; exit 1; }
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)

export BLENDER_USER_SCRIPTS BLENDER_USER_CONFIG
BLENDER_USER_SCRIPTS=$(mktemp -d); BLENDER_USER_CONFIG=$BLENDER_USER_SCRIPTS
trap 'rm -rf "$BLENDER_USER_SCRIPTS"' EXIT

# The light conversion under test (see above).
$PY -c 'import json, math, sys
json.dump({"sun_irradiance_per_strength": 1.0,
           "point_irradiance_at_1_per_watt": 1.0 / (4.0 * math.pi),
           "source": "law measured in issue 5, not re-measured"}, open(sys.argv[1], "w"), indent=2)' \
  "$OUT/light_units.json"

timed() {  # timed LABEL CMD...: runs CMD, prints its wall seconds
  local t0 t1
  t0=$(date +%s.%N)
  "$@"
  t1=$(date +%s.%N)
  printf '%s\t%.2f\n' "$1" "$(echo "$t1 - $t0" | bc)" >> "$OUT/$NAME/seconds.tsv"
}
blender_run() {  # quiet unless Blender fails
  local log=$OUT/$NAME/blender.log
  if ! "$BLENDER" -b --factory-startup --python-exit-code 1 "$@" > "$log" 2>&1; then
    cat "$log" >&2; return 1
  fi
  grep -E '^volume_render:' "$log" || true
}
cb_render() { "$CLOTHBAKE" render "$SCENE" -o "$OUT/$NAME/clothbake.exr" --spp "$cb_spp" --quiet; }
cb_volume() { "$CLOTHBAKE" volume "$SCENE" -o "$OUT/$NAME/volume" > /dev/null; }
tile() { "$PY" "$ROOT/lab/common/tile_volume.py" "$SCENE" "$OUT/$NAME/volume" "$OUT/$NAME/tiled.vdb" > /dev/null; }
cycles() {
  # shellcheck disable=SC2086
  blender_run -P "$ROOT/lab/common/volume_render.py" -- "$SCENE" "$OUT/$NAME/volume" \
    "$OUT/$NAME/tiled.vdb" "$OUT/light_units.json" "$OUT/$NAME" --samples "$1" --seed 1,2 \
    --tag cycles $CY_ARGS
}

status=0
for NAME in $SCENES; do
  SCENE=$ROOT/testscenes/$NAME/cycles_check.json
  mkdir -p "$OUT/$NAME"
  : > "$OUT/$NAME/seconds.tsv"
  up=${NAME^^}
  spp_var=${up}_CY_SPP; cb_spp_var=${up}_CB_SPP
  spp=${!spp_var}; cb_spp=${!cb_spp_var}
  echo "== $NAME: clothbake volume, tile, clothbake render ($cb_spp spp), Cycles (2 x $spp spp)"
  if [[ ${REUSE:-0} == 1 && -f $OUT/$NAME/clothbake.exr && -f $OUT/$NAME/tiled.vdb ]]; then
    echo "   reusing $OUT/$NAME: volume, tiled.vdb, clothbake.exr"
  else
    timed cb_volume
    timed tile
    timed cb_render
  fi
  timed cycles "$spp"
  args=()
  [[ -n $FIGURES ]] && { mkdir -p "$FIGURES"; args+=(--figure "$FIGURES/cycles_check_$NAME.png"); }
  if [[ $CHECK == 1 ]]; then
    psnr_var=${up}_MIN_PSNR; psnr4_var=${up}_MIN_PSNR4; ratio_var=${up}_RATIO
    args+=(--min-psnr "${!psnr_var:?$psnr_var not set}" --min-psnr4 "${!psnr4_var:?$psnr4_var not set}"
           --ratio-range "${!ratio_var:?$ratio_var not set}")
  fi
  "$PY" "$ROOT/lab/cycles_check/cycles_check_report.py" "$NAME" "$CLOTHBAKE" "$OUT/$NAME/clothbake.exr" \
    "$OUT/$NAME/cycles_s${spp}_seed1.exr" "$OUT/$NAME/cycles_s${spp}_seed2.exr" "$OUT/$NAME" \
    "${args[@]}" || status=1
  sed 's/^/   seconds: /' "$OUT/$NAME/seconds.tsv"
done
exit $status
