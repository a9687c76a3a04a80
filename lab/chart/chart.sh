#!/usr/bin/env bash
# Speed against accuracy (docs/design/results.md): sweeps every method clothbake
# offers on the paper scene (half resolution) and on testscenes/flat (grazing
# views, isotropic shading, where Cycles can also render the real volume),
# writing out/chart/<scene>/points.csv and charts as PNG and SVG under
# docs/images/chart_<scene>.{png,svg} with the points as a Markdown table
# (chart_<scene>.md). About 30 minutes on the 2-core machine;
# run it on an otherwise idle machine (the seconds are the point).
#   lab/chart/chart.sh [--quick] [SCENE...]     (scenes: paper flat, the default)
source "$(dirname "$0")/../../scripts/lib.sh"
install_packages
build_all
quick=()
if [[ ${1:-} == --quick ]]; then
  quick=(--quick --runs 1 --ref-spp 16)
  shift
fi
scenes=("$@")
((${#scenes[@]})) || scenes=(paper paper_far flat)
out="$CLOTHBAKE_ROOT/out/chart"
mkdir -p "$out"
{ git -C "$CLOTHBAKE_ROOT" rev-parse --short HEAD; lscpu | grep -E "Model name|^CPU\(s\)"; free -g | head -2; blender --version 2>/dev/null | head -1; } >"$out/machine.txt"
for scene in "${scenes[@]}"; do
  scale=1.0
  [[ $scene == paper ]] && scale=0.5
  extra=()
  timing="$CLOTHBAKE_ROOT/out/flat/vol/volume_seed1_timing.json"
  if [[ $scene == flat && ! -f $timing && ${#quick[@]} -eq 0 ]]; then
    # The real-volume route's renders (about 5 minutes) are made once and reused.
    log "Cycles real-volume renders of the flat scene (lab/cycles_timing/cycles_volume_timing.sh)"
    CLOTHBAKE="$CLOTHBAKE_BUILD/baker/clothbake" bash "$CLOTHBAKE_ROOT/lab/cycles_timing/cycles_volume_timing.sh"
  fi
  if [[ $scene == flat && -f $timing ]]; then
    # Cycles rendering the real volume (lab/cycles_timing/cycles_volume_timing.sh, run
    # before): its renders, timed inside Blender (load + render), join the chart.
    mkdir -p "$out/flat"
    /usr/bin/python3 - "$timing" "$CLOTHBAKE_ROOT" >"$out/flat/extra_points.csv" <<'PY'
import csv, json, os, sys
t = json.load(open(sys.argv[1]))
w = csv.writer(sys.stdout)
w.writerow(["series", "label", "seconds", "image", "setting"])
for run in t["runs"]:
    w.writerow(["Cycles real volume (VDB)", f"{run['samples']} samples",
                round(run["render_seconds"] + t["load_seconds"], 3),
                os.path.join(sys.argv[2], run["exr"]), "volume_bounces=0, isotropic"])
PY
    extra=(--extra-points "$out/flat/extra_points.csv")
  fi
  log "sweep on $scene (resolution x $scale)"
  /usr/bin/python3 "$CLOTHBAKE_ROOT/lab/chart/chart.py" "$CLOTHBAKE_ROOT/testscenes/$scene/scene.json" \
    --name "$scene" --out "$out/$scene" --scale "$scale" "${quick[@]}" "${extra[@]}"
  /usr/bin/python3 "$CLOTHBAKE_ROOT/lab/chart/plot_chart.py" "$out/$scene/points.csv" \
    "$CLOTHBAKE_ROOT/docs/images/chart_$scene" --title "clothbake: $scene scene, error against time" \
    --machine "$out/machine.txt"
done
log "done: $out/*/points.csv, docs/images/chart_{paper,flat}.{png,svg,md}"
