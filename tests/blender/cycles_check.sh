#!/usr/bin/env bash
# CTest blender.cycles_check: clothbake's reference renderer (isotropic mode)
# against Blender 3.4 Cycles rendering the same volumes as real OpenVDB volumes
# with volume_bounces = 0 (lab/cycles_check/cycles_check.sh; docs/design/results.md, "An
# independent check: Cycles real volumes"). Fails when the mean ratio or the
# PSNR of either scene leaves its bound.
#
#   bash cycles_check.sh BLENDER_EXE CLOTHBAKE_EXE SOURCE_DIR
#
# BOUNDS (measured on the 2-core machine, Blender 3.4.1, docs/design/results.md; the
# seeds are fixed, and three runs gave the same figures to the last digit).
# 113 to 124 CPU seconds: about 1 to 1.5 minutes on the idle machine. "noise" is the Cycles picture's own,
# from its two seeds; the mean ratio's noise sigma is under 1e-4 in both.
#
# slab (64 x 64, Cycles 2 x 512 spp, clothbake 64 spp; uniform, so every
# pixel has the same expectation and the peak is the mean): measured mean
# ratio 1.0009, PSNR 51.12 dB (noise alone 52.6 dB: 0.24% per pixel), 59.60 dB
# after 4 x 4 averaging (noise 0.06%, the rest the +0.09% mean offset, Cycles'
# one-voxel march).
#   - ratio in [0.995, 1.005]: +-0.5%, 50 noise sigmas and 5x the measured
#     offset. A factor 2 in extinction moves it by -46% (the see-through
#     exp(-1.8) becomes exp(-3.6)), 10% by -9%; the sun's strength moves it
#     by 0.44% per 1%.
#   - PSNR >= 48 dB (3 dB below: the RMSE may grow by 41%; the estimate of
#     the RMSE from 4096 x 3 values moves by ~1%). A uniform error of 0.4%
#     alone gives 48 dB.
#   - PSNR after 4 x 4 >= 54 dB: an RMSE of 0.2% of the peak, twice the
#     measured 0.10% (noise contributes 0.06%); any uniform error of 0.2%.
#
# flat (200 x 128 woven cloth, Cycles 2 x 256 spp, clothbake 16 spp):
# measured mean ratio 1.0077, PSNR 37.08 dB (noise alone 39.57 dB: 2.38% per
# pixel; systematic 2.10%), 43.73 dB after 4 x 4 averaging (noise 0.60%,
# systematic 1.15%). The +0.77% and the systematic RMSE are Cycles' trilinear
# lookup and its one-voxel march (docs/design/results.md: 2 x finer cells leave
# +0.30% and 0.84%).
#   - ratio in [1.002, 1.014]: the measurement +-0.6% (60 noise sigmas); the
#     lower end stays below the 1.0030 measured with the lookup blur and the
#     step halved, so Cycles coming closer to clothbake does not fail it. A
#     1% error in the sun's strength moves the ratio by about 0.9%; a point
#     light of 4 pi^2 I watts instead of 4 pi I moved it to 1.1787 (tried).
#   - PSNR >= 36 dB: 1.1 dB below (RMSE +13%). Seen when the volume is
#     misplaced or mis-scaled (2 x 128 spp, docs/design/results.md): half a voxel
#     off 26.9 dB, one voxel off 24.2 dB, 3 x the extinction 29.0 dB, cubic
#     lookup 32.4 dB.
#   - PSNR after 4 x 4 >= 42.5 dB: 1.2 dB below (RMSE +15%); the same faults
#     give 31.4, 27.7 and 38.0 dB.
#
# Tried (docs/design/results.md, "The test and its bounds"): the extinction doubled
# in lab/common/volume_render.py fails this test (slab ratio 0.5414,
# PSNR 6.8 dB; flat PSNR 31.9 dB, 37.0 dB after 4 x 4); the point light at
# 4 pi^2 I watts fails the flat scene (ratio 1.1787, PSNR 20.8 dB).
set -euo pipefail

if [[ $# -ne 3 ]]; then
  echo "usage: bash cycles_check.sh BLENDER_EXE CLOTHBAKE_EXE SOURCE_DIR" >&2
  exit 2
fi
blender=$1 clothbake=$2 src=$3
[[ -x $blender ]] || { echo "FAIL: Blender not found: $blender" >&2; exit 1; }
[[ -x $clothbake ]] || { echo "FAIL: clothbake not found: $clothbake" >&2; exit 1; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/cycles_check.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

export BLENDER=$blender CLOTHBAKE=$clothbake
export SLAB_CY_SPP=512 SLAB_CB_SPP=64 FLAT_CY_SPP=256 FLAT_CB_SPP=16
export SLAB_RATIO=0.995,1.005 SLAB_MIN_PSNR=48 SLAB_MIN_PSNR4=54
export FLAT_RATIO=1.002,1.014 FLAT_MIN_PSNR=36 FLAT_MIN_PSNR4=42.5
bash "$src/lab/cycles_check/cycles_check.sh" "$tmp" --check
