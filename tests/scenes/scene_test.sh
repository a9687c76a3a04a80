#!/usr/bin/env bash
# Renders a test scene at its own settings and compares it with the scene's
# stored reference (64 spp, another seed, box-averaged 2 x 2): metric relative
# RMSE over RGB after the same 2 x 2 averaging, bound given by the caller
# (derived in the scene's README from the measured noise of two seeds).
set -eu
exe=$1 scene=$2 reference=$3 bound=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$exe" render "$scene" -o "$tmp/test.exr" --quiet
"$exe" compare "$reference" "$tmp/test.exr" --downsample 2 --max-relative-rmse "$bound" \
  --heatmap "$tmp/heat.png"
