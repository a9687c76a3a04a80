#!/usr/bin/env bash
# The farm's scaling figure (docs/guide/farm.md, "Scaling"): one material bake on
# this machine, then the same bake through a one-machine Slurm cluster in
# 1, 2, 4, 8 shards, each task given every core (--cpus-per-task $(nproc)), so
# the tasks run one after another and each shard's time is what one node like
# this machine would take for it. Every merged folder is checked byte for byte
# against the single bake. Writes OUT_DIR/scaling.json and draws
# OUT_DIR/farm_scaling.png (scaling_report.py). About 6 min on 2 cores.
#   lab/farm_scaling/scaling.sh [OUT_DIR] [--shards "1 2 4 8"] [-- MATERIAL_OPTIONS]
# MATERIAL_OPTIONS default to the paper cloth's material at 16 texels per repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
farm_dir=$root/scripts/farm
source "$root/scripts/lib.sh"

out=$root/out/farm_scaling shard_list="1 2 4 8" mat_opts=(--texels 16)
if [[ $# -gt 0 && $1 != -* ]]; then out=$1; shift; fi
while (($# > 0)); do
  case $1 in
    --shards) shard_list=$2; shift 2 ;;
    --) shift; mat_opts=("$@"); break ;;
    *) echo "scaling.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
exe=$CLOTHBAKE_BUILD/baker/clothbake
[[ -x $exe ]] || { install_packages; build_all; }
spec=$root/testscenes/paper/cloth.json
cores=$(nproc)
mkdir -p "$out"
out=$(realpath "$out")
work=$(mktemp -d /tmp/clothbake-farm-scaling.XXXXXX)
chmod 755 "$work"  # munged: every folder above its socket searchable by all
export CLOTHBAKE_CLUSTER_DIR=$work/cluster CLOTHBAKE_FARM_POLL=0.5
cleanup() { "$farm_dir/local-cluster.sh" stop >/dev/null 2>&1 || true; rm -rf "$work"; }
trap cleanup EXIT
"$farm_dir/local-cluster.sh" start
eval "$("$farm_dir/local-cluster.sh" env)"
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }'; }

log "the single bake on this machine ($cores threads): clothbake material $spec ${mat_opts[*]}"
t0=$(now)
"$exe" material "$spec" -o "$work/single" --threads "$cores" "${mat_opts[@]}" --quiet >/dev/null
single=$(since "$t0")
log "single bake: $single s"

runs=$work/runs.tsv
printf 'shards\twall_seconds\tshard_seconds\tmerge_seconds\n' >"$runs"
for n in $shard_list; do
  log "$n shard(s) through the farm"
  t0=$(now)
  "$farm_dir/submit.sh" material "$spec" -o "$work/farm_$n" --shards "$n" --cpus-per-task "$cores" \
    --clothbake "$exe" --wait -- "${mat_opts[@]}" >"$work/farm_$n.summary" 2>"$work/farm_$n.err" ||
    { cat "$work/farm_$n.err" "$work/farm_$n.summary"; exit 1; }
  wall=$(since "$t0")
  for f in "$work/single"/*; do
    cmp -s "$f" "$work/farm_$n/$(basename "$f")" || { echo "FAIL: $n shards: $(basename "$f") differs"; exit 1; }
  done
  status=$(ls -d "$work/farm_$n.logs"/tasks-*)/status
  shards_s=$(for ((i = 1; i <= n; i++)); do sed -n 's/.*state=done .*seconds=\([0-9.]*\).*/\1/p' "$status/$i"; done | paste -sd,)
  merge_s=0  # --shards 1 bakes straight into the output
  [[ -f $status/merge ]] && merge_s=$(sed -n 's/.*state=done .*seconds=\([0-9.]*\).*/\1/p' "$status/merge")
  log "$n shard(s): wall $wall s, shards [$shards_s] s, merge $merge_s s; merged bytes equal the single bake's"
  printf '%s\t%s\t%s\t%s\n' "$n" "$wall" "$shards_s" "$merge_s" >>"$runs"
done
/usr/bin/python3 "$(dirname "$0")/scaling_report.py" "$runs" --single-seconds "$single" --cores "$cores" \
  --options "${mat_opts[*]}" --json "$out/scaling.json" --png "$out/farm_scaling.png"
cp "$runs" "$out/runs.tsv"
log "wrote $out/runs.tsv, $out/scaling.json and $out/farm_scaling.png"
