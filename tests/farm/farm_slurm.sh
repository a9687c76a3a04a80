#!/usr/bin/env bash
# The farm scripts on a one-machine Slurm cluster (docs/guide/farm.md):
# scripts/farm/local-cluster.sh in a private folder (its own munge key,
# ports, state; stopped and deleted at the end), scripts/farm/submit.sh
# against it. Checks, each against the same work done by one clothbake run:
#  - a material in 4 shards plus the merge, and in 1: every file byte for byte;
#  - a library of two specs as one array: each folder byte for byte;
#  - the same with task 2's first attempt killed (SIGKILL) after writing its
#    part under the temporary name: requeued, stale temporary removed, same bytes;
#  - a task that fails on every attempt (no retries): --wait exits non-zero,
#    the merge never runs, the output folder is as it was;
#  - three frames (reference route) and two (lookup route, from the farm's
#    material): every EXR byte for byte; one by Blender's headless route: the
#    same pixels;
#  - a per-scene bake in 4 shards plus the merge: every EXR byte for byte, the
#    manifest equal but for "statistics" (wall-clock seconds; the merge's
#    record of its parts);
#  - a job cancelled (scancel) while its merge holds the finished output
#    under its temporary name: the output folder as it was, no temporary left.
# Needs slurm-wlm and munge (scripts/packages.txt) and root (slurmd starts
# the jobs). About a minute on 2 cores.
#   farm_slurm.sh CLOTHBAKE_EXE SOURCE_DIR
set -u
exe=$(realpath "$1") root=$(realpath "$2")
fail() {
  echo "FAIL: $*"
  exit 1
}
for p in munged slurmctld slurmd sbatch; do
  command -v "$p" >/dev/null || fail "$p not found: install slurm-wlm and munge (scripts/packages.txt)"
done
[[ $(id -u) -eq 0 ]] || fail "run as root: slurmd starts the jobs as their users"

tmp=$(mktemp -d /tmp/clothbake-farm-test.XXXXXX)
chmod 755 "$tmp"  # munged: every folder above its socket searchable by all
export CLOTHBAKE_CLUSTER_DIR=$tmp/cluster CLOTHBAKE_FARM_POLL=1
unset CLOTHBAKE_FARM_FAULT CLOTHBAKE_TEST_HOLD_UNFINISHED
cluster=$root/scripts/farm/local-cluster.sh
submit=$root/scripts/farm/submit.sh
started=0
cleanup() {
  if ((started)); then
    "$cluster" stop >/dev/null 2>&1 || echo "warning: local-cluster.sh stop failed"
  fi
  [[ -n ${CLOTHBAKE_FARM_TEST_KEEP:-} ]] && echo "kept $tmp" || rm -rf "$tmp"
}
trap cleanup EXIT
cd "$tmp" || fail "cd $tmp"

# --- the cluster: start (twice: idempotent), status ----------------------------
if ! "$cluster" status >/dev/null 2>&1; then
  "$cluster" start 2>"$tmp/start.err" || fail "local-cluster.sh start: $(cat "$tmp/start.err")"
  started=1
fi
"$cluster" start 2>"$tmp/start2.err" || fail "a second start: $(cat "$tmp/start2.err")"
"$cluster" status >"$tmp/status.txt" || fail "status after start: $(cat "$tmp/status.txt")"
grep -q 'idle' "$tmp/status.txt" || fail "the node is not idle: $(cat "$tmp/status.txt")"
eval "$("$cluster" env)"
echo "ok   local cluster up in $CLOTHBAKE_CLUSTER_DIR, started twice"

same_folders() {  # what, expected folder, folder: every file, byte for byte
  local f n=0
  [[ -d $3 ]] || fail "$1: $3 missing"
  diff <(cd "$2" && ls -A) <(cd "$3" && ls -A) >"$tmp/ls.diff" ||
    fail "$1: other files: $(cat "$tmp/ls.diff")"
  for f in "$2"/*; do
    cmp -s "$f" "$3/$(basename "$f")" || fail "$1: $(basename "$f") differs from the single run's"
    n=$((n + 1))
  done
  ((n > 0)) || fail "$1: no files in $2"
  echo "ok   $1: $n files byte-identical to the single run"
}
farm() {  # log name, submit.sh subcommand, its arguments...
  local name=$1 kind=$2
  shift 2
  "$submit" "$kind" --clothbake "$exe" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err"
}

# --- a material in 4 shards ----------------------------------------------------
spec=$root/testscenes/paper/cloth.json
mat_opts=(--texels 8 --directions 4 --light-directions 4 --spp 1 --field-supersample 1)
"$exe" material "$spec" -o "$tmp/mat_single" "${mat_opts[@]}" --quiet >/dev/null ||
  fail "the single material bake"
farm mat material "$spec" -o "$tmp/mat" --shards 4 --wait -- "${mat_opts[@]}" ||
  fail "material through the farm: $(cat "$tmp/mat.err" "$tmp/mat.out")"
same_folders "material, 4 shards + merge" "$tmp/mat_single" "$tmp/mat"
farm mat1 material "$spec" -o "$tmp/mat1" --shards 1 --wait -- "${mat_opts[@]}" ||
  fail "material in one shard: $(cat "$tmp/mat1.err" "$tmp/mat1.out")"
same_folders "material, 1 shard (no merge)" "$tmp/mat_single" "$tmp/mat1"

# --- a library: two specs, one task each; two specs of one name refused --------
mkdir -p "$tmp/lib"
cp "$root/testscenes/paper/cloth.json" "$tmp/lib/paper.json"
cp "$root/testscenes/slab/cloth.json" "$tmp/lib/slab.json"
for name in paper slab; do  # the manifest names its spec: bake the copies
  "$exe" material "$tmp/lib/$name.json" -o "$tmp/${name}_single" "${mat_opts[@]}" --quiet >/dev/null ||
    fail "the single $name material"
done
farm lib material "$tmp/lib/paper.json" "$tmp/lib/slab.json" -o "$tmp/library" --wait -- "${mat_opts[@]}" ||
  fail "a library through the farm: $(cat "$tmp/lib.err" "$tmp/lib.out")"
same_folders "library, paper" "$tmp/paper_single" "$tmp/library/paper"
same_folders "library, slab" "$tmp/slab_single" "$tmp/library/slab"
if farm libsame material "$spec" "$root/testscenes/slab/cloth.json" -o "$tmp/library2" -- "${mat_opts[@]}"; then
  fail "two specs named cloth were submitted"
fi
grep -q "two specs named cloth" "$tmp/libsame.err" || fail "the refusal does not name the spec: $(cat "$tmp/libsame.err")"
[[ ! -e $tmp/library2 ]] || fail "the refused library made $tmp/library2"
echo "ok   a library of 2 specs: each folder byte-identical to its single bake; 2 specs of one name refused"

# --- the same with task 2 killed mid-write on its first attempt -----------------
CLOTHBAKE_FARM_FAULT=kill:2 farm kill material "$spec" -o "$tmp/mat_kill" --shards 4 --wait -- "${mat_opts[@]}" ||
  fail "material with task 2 killed: $(cat "$tmp/kill.err" "$tmp/kill.out")"
log2=$(ls "$tmp"/mat_kill.logs/cb-material-mat_kill-*_2.out)
grep -q 'killed pid .* with SIGKILL before its rename; left: part-2.tmp-' "$log2" ||
  fail "task 2 was not killed holding its temporary: $(cat "$log2")"
grep -q 'attempt 2 of 3' "$log2" || fail "task 2 was not requeued: $(cat "$log2")"
grep -q 'removed stale temporary .*part-2.tmp-' "$log2" ||
  fail "the retry did not remove the killed attempt's temporary: $(cat "$log2")"
[[ $(wc -l <"$(ls -d "$tmp"/mat_kill.logs/tasks-*)/status/2") -eq 2 ]] || fail "task 2: not two attempts"
[[ -z $(ls -d "$tmp"/mat_kill.parts/*.tmp-* 2>/dev/null) ]] || fail "a temporary part is left"
same_folders "material, task 2 killed (SIGKILL) and requeued" "$tmp/mat_single" "$tmp/mat_kill"

# --- a task failing every attempt: no merge, the output as it was ----------------
cp -a "$tmp/mat_single" "$tmp/mat_fail"
if CLOTHBAKE_FARM_FAULT=fail:3 farm failing material "$spec" -o "$tmp/mat_fail" --shards 4 --max-retries 0 --wait -- "${mat_opts[@]}"; then
  fail "--wait exited 0 with task 3 failed: $(cat "$tmp/failing.out")"
fi
grep -Eq '^3 +FAILED' "$tmp/failing.out" || fail "the summary does not show task 3 failed: $(cat "$tmp/failing.out")"
grep -Eq '^merge +CANCELLED.*DependencyNeverSatisfied' "$tmp/failing.out" ||
  fail "the summary does not show the merge cancelled: $(cat "$tmp/failing.out")"
same_folders "a task failed: the output folder as it was" "$tmp/mat_single" "$tmp/mat_fail"

# --- frames: reference and lookup routes ---------------------------------------
# The paper scene at half resolution, the sun turning a little per frame.
mkdir -p "$tmp/scenes"
/usr/bin/python3 - "$root/testscenes/paper" "$tmp/scenes" <<'PY' || fail "writing the frames' scenes"
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
for frame in (1, 2, 3):
    s = json.load(open(os.path.join(src, "scene.json")))
    s["camera"]["resolution"] = [r // 2 for r in s["camera"]["resolution"]]
    s["lights"][0]["direction"][0] = 0.4 + 0.1 * frame
    for o in s["objects"]:
        for key in ("mesh", "cloth"):
            o[key] = os.path.join(src, o[key])
    json.dump(s, open(os.path.join(dst, "frame_%04d.json" % frame), "w"), indent=2)
PY
farm frames frames 'scenes/frame_%04d.json' --range 1-3 -o "$tmp/frames" --wait -- --spp 1 ||
  fail "frames through the farm: $(cat "$tmp/frames.err" "$tmp/frames.out")"
farm lframes frames "$tmp/scenes/frame_0001.json" "$tmp/scenes/frame_0003.json" -o "$tmp/lframes" \
  --route lookup --material "$tmp/mat" --wait -- --spp 1 ||
  fail "lookup frames through the farm: $(cat "$tmp/lframes.err" "$tmp/lframes.out")"
mkdir -p "$tmp/frames_single" "$tmp/lframes_single"
for i in 1 2 3; do
  "$exe" render "$tmp/scenes/frame_000$i.json" -o "$tmp/frames_single/frame_000$i.exr" --spp 1 --quiet ||
    fail "single render of frame $i"
done
for i in 1 3; do
  "$exe" lookup-render "$tmp/scenes/frame_000$i.json" "$tmp/mat_single" \
    -o "$tmp/lframes_single/frame_000$i.exr" --spp 1 --quiet || fail "single lookup-render of frame $i"
done
same_folders "3 frames, reference route" "$tmp/frames_single" "$tmp/frames"
same_folders "2 frames, lookup route from the farm's material" "$tmp/lframes_single" "$tmp/lframes"
# The Blender route (Cycles from the farm's material), when Blender is here as
# the Blender tests need it: the same pixels as a headless render run by hand
# (not the same bytes: Blender's EXR header holds its own fields).
if blender=$(command -v blender); then
  farm bframes frames "$tmp/scenes/frame_0002.json" -o "$tmp/bframes" --route blender \
    --material "$tmp/mat" --wait -- --samples 2 ||
    fail "Blender frames through the farm: $(cat "$tmp/bframes.err" "$tmp/bframes.out")"
  "$blender" -b --factory-startup --python-exit-code 1 -P "$root/blender_addon/headless_render.py" -- \
    "$tmp/scenes/frame_0002.json" "$tmp/mat" "$tmp/bframe_single.exr" --samples 2 --threads 1 \
    >"$tmp/bframe_single.log" 2>&1 || fail "the single Blender render: $(tail -5 "$tmp/bframe_single.log")"
  max=$("$exe" compare "$tmp/bframe_single.exr" "$tmp/bframes/frame_0002.exr" --json |
    /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["max_error"])') ||
    fail "comparing the Blender frames"
  [[ $max == 0.0 ]] || fail "the Blender frame through the farm differs from the single render (max error $max)"
  echo "ok   1 frame, Blender route from the farm's material: the same pixels as the single render"
else
  echo "note: blender not found, the Blender route is not tried (scripts/packages.txt installs it)"
fi

# --- a per-scene bake in 4 shards ------------------------------------------------
scene=$root/testscenes/paper/scene.json
bake_opts=(--directions 3 --texels 4 --spp 1)
"$exe" bake "$scene" -o "$tmp/bake_single" "${bake_opts[@]}" --quiet >/dev/null || fail "the single bake"
farm bake bake "$scene" -o "$tmp/bake" --shards 4 --wait -- "${bake_opts[@]}" ||
  fail "bake through the farm: $(cat "$tmp/bake.err" "$tmp/bake.out")"
n=0
for f in "$tmp"/bake_single/*.exr; do
  cmp -s "$f" "$tmp/bake/$(basename "$f")" || fail "bake: $(basename "$f") differs from the single bake's"
  n=$((n + 1))
done
((n > 0)) || fail "bake: no lookup images"
[[ $(ls "$tmp/bake" | wc -l) -eq $(ls "$tmp/bake_single" | wc -l) ]] || fail "bake: other files than the single bake's"
/usr/bin/python3 - "$tmp/bake_single/manifest.json" "$tmp/bake/manifest.json" <<'PY' ||
import json, sys
def flat(v, path=""):
    if isinstance(v, dict):
        for k, x in v.items():
            yield from flat(x, f"{path}.{k}" if path else k)
    elif isinstance(v, list):
        for i, x in enumerate(v):
            yield from flat(x, f"{path}[{i}]")
    else:
        yield path, v
a, b = (json.load(open(p)) for p in sys.argv[1:])
for m in (a, b):
    m.pop("statistics", None)  # seconds; the merge's record of its parts
fa, fb = dict(flat(a)), dict(flat(b))
diff = [(k, fa.get(k), fb.get(k)) for k in sorted(set(fa) | set(fb)) if fa.get(k) != fb.get(k)]
for k, x, y in diff[:10]:
    print(f"  {k}: single {x!r}, farm {y!r}")
sys.exit(1 if diff else 0)
PY
  fail "bake: the merged manifest differs from the single bake's (above)"
echo "ok   bake, 4 shards + merge: $n lookup images byte-identical, manifest equal but for statistics"

# --- cancelled while the merge holds its temporary: the output as it was --------
before=$(cd "$tmp/mat" && sha256sum -- *)
# Another seed: a merge that got through would change the folder.
CLOTHBAKE_FARM_FAULT=hold:merge:120 farm cancel material "$spec" -o "$tmp/mat" --shards 2 \
  -- "${mat_opts[@]}" --seed 7 || fail "submitting the job to cancel: $(cat "$tmp/cancel.err")"
read -r array_job merge_job <"$tmp/cancel.out"
merge_log=$tmp/mat.logs/cb-merge-mat-$merge_job.out
for ((i = 0; i < 240; i++)); do
  grep -q 'holding unfinished' "$merge_log" 2>/dev/null && break
  sleep 0.5
done
grep -q 'holding unfinished' "$merge_log" 2>/dev/null ||
  fail "the merge never reached its rename in 120 s: $(cat "$merge_log" 2>&1)
$(squeue -r -j "$array_job,$merge_job" -o '%i %T %r %M' 2>&1)
$(tail -5 "$CLOTHBAKE_CLUSTER_DIR/log/slurmctld.log")
$(tail -n 5 "$tmp"/mat.logs/cb-material-mat-"$array_job"_*.out 2>&1)"
ls -d "$tmp"/mat.tmp-* >/dev/null 2>&1 || fail "no temporary output while the merge holds"
scancel "$array_job" "$merge_job" || fail "scancel"
for ((i = 0; i < 120; i++)); do
  [[ -z $(squeue -h -j "$array_job,$merge_job" 2>/dev/null) ]] && break
  sleep 0.5
done
[[ -z $(squeue -h -j "$array_job,$merge_job" 2>/dev/null) ]] || fail "the cancelled jobs are still queued"
sleep 1
[[ $(cd "$tmp/mat" && sha256sum -- *) == "$before" ]] || fail "the cancelled job changed $tmp/mat"
[[ -z $(ls -d "$tmp"/mat.tmp-* "$tmp"/mat.old-* 2>/dev/null) ]] || fail "the cancelled merge left a temporary"
echo "ok   cancelled in the merge: the output folder as it was, no temporary left"

"$cluster" stop 2>/dev/null || fail "local-cluster.sh stop"
"$cluster" stop 2>/dev/null || fail "a second stop"
started=0
"$cluster" status >/dev/null 2>&1 && fail "status says up after stop"
echo "ok   local cluster stopped (twice)"
