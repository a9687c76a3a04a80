#!/usr/bin/env bash
# clothbake on a Slurm cluster (docs/guide/farm.md): array jobs for a material in
# shards, a per-scene bake in shards, or a sequence of frames.
#
#   submit.sh material SPEC_OR_SCENE -o DIR --shards N [OPTIONS] [-- MATERIAL_OPTIONS]
#       N tasks `clothbake material SPEC -o DIR.parts/part-I --shard I/N ...`,
#       then, after all of them succeeded, `clothbake merge DIR.parts/part-* -o DIR`
#       (--shards 1: one task baking straight into DIR, no merge)
#   submit.sh material SPEC... -o OUTDIR [OPTIONS] [-- MATERIAL_OPTIONS]
#       a library: one task per spec, OUTDIR/<spec name>/ (each bake whole)
#   submit.sh bake SCENE -o DIR --shards N [OPTIONS] [-- BAKE_OPTIONS]
#       the same for `clothbake bake SCENE -o DIR.parts/part-I --shard I/N ...`
#   submit.sh frames SCENE... -o OUTDIR [--route R] [--material DIR] [OPTIONS] [-- RENDER_OPTIONS]
#   submit.sh frames PATTERN --range A-B -o OUTDIR ...
#       one task per scene JSON, OUTDIR/<scene name>.exr; PATTERN is printf-style
#       (scenes/frame_%04d.json with --range 1-3: frame_0001.json ... frame_0003.json)
#       --route reference  clothbake render SCENE -o OUT.exr            (default)
#       --route lookup     clothbake lookup-render SCENE DIR -o OUT.exr (needs --material)
#       --route blender    blender -b ... headless_render.py -- SCENE DIR OUT.exr (needs --material)
#
# OPTIONS (all subcommands):
#   --partition P, --account A, --time T, --mem M   passed to sbatch
#   --cpus-per-task C   cores per task (default 1); the program gets --threads C
#                       unless the options after -- name --threads
#   --max-retries R     a failed task is requeued up to R times (default 2)
#   --clothbake PATH    the program's path on the nodes (default: this checkout's build)
#   --blender PATH      Blender on the nodes (route blender; default: blender)
#   --source DIR        this repository on the nodes (route blender; default: this checkout)
#   --logs DIR          logs and task files (default: DIR.logs / OUTDIR.logs beside the output);
#                       each task's log is %x-%A_%a.out, the merge's %x-%j.out
#   --wait              wait, show progress, print a summary; exit 1 if anything failed
#   -h, --help          this text
# Paths are made absolute: inputs, outputs, logs and the program must be on a
# file system the nodes share. The submitting folder is the jobs' working folder.
set -euo pipefail

farm_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo_root=$(cd "$farm_dir/../.." && pwd)

# A refused submission leaves nothing: what this run made for its task
# files is removed unless a job was submitted.
made_logs="" made_tasks="" submitted=0
die() {
  printf 'submit.sh: error: %s\n' "$*" >&2
  if ((!submitted)); then
    [[ -n $made_tasks ]] && rm -rf -- "$made_tasks"
    [[ -n $made_logs ]] && rmdir -- "$made_logs" 2>/dev/null
  fi
  exit 2
}
say() { printf '%s\n' "$*" >&2; }
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }

# --- arguments ---------------------------------------------------------------
kind=${1:-}
case $kind in
  material | bake | frames) shift ;;
  -h | --help | help)
    usage
    exit 0
    ;;
  "") usage >&2; die "expected a subcommand: material, bake or frames" ;;
  *) usage >&2; die "unknown subcommand '$kind' (expected material, bake or frames)" ;;
esac

inputs=() out="" shards="" range="" route=reference material_dir="" wait=0
partition="" account="" time_limit="" mem="" cpus=1 retries=2 logs=""
clothbake="" blender=blender source_dir=$repo_root passthrough=()

need_value() {  # option, remaining argument count
  (($2 >= 2)) || die "$1: missing value"
}
while (($# > 0)); do
  case $1 in
    -o | --out) need_value "$1" $#; out=$2; shift 2 ;;
    --shards) need_value "$1" $#; shards=$2; shift 2 ;;
    --range) need_value "$1" $#; range=$2; shift 2 ;;
    --route) need_value "$1" $#; route=$2; shift 2 ;;
    --material) need_value "$1" $#; material_dir=$2; shift 2 ;;
    --partition) need_value "$1" $#; partition=$2; shift 2 ;;
    --account) need_value "$1" $#; account=$2; shift 2 ;;
    --time) need_value "$1" $#; time_limit=$2; shift 2 ;;
    --mem) need_value "$1" $#; mem=$2; shift 2 ;;
    --cpus-per-task) need_value "$1" $#; cpus=$2; shift 2 ;;
    --max-retries) need_value "$1" $#; retries=$2; shift 2 ;;
    --clothbake) need_value "$1" $#; clothbake=$2; shift 2 ;;
    --blender) need_value "$1" $#; blender=$2; shift 2 ;;
    --source) need_value "$1" $#; source_dir=$2; shift 2 ;;
    --logs) need_value "$1" $#; logs=$2; shift 2 ;;
    --wait) wait=1; shift ;;
    -h | --help) usage; exit 0 ;;
    --)
      shift
      passthrough=("$@")
      break
      ;;
    -*) die "unknown option '$1' (options for clothbake go after --)" ;;
    *) inputs+=("$1"); shift ;;
  esac
done

whole_number() {  # option, value, minimum
  if [[ $2 =~ ^[0-9]+$ ]] && (($2 >= $3)); then return; fi
  die "$1: expected a whole number >= $3, got '$2'"
}
[[ -n $out ]] || die "-o: missing (the output folder)"
whole_number --cpus-per-task "$cpus" 1
whole_number --max-retries "$retries" 0
abs() { realpath -m -- "$1"; }
out=$(abs "$out")
[[ -d $(dirname "$out") ]] || die "-o: the folder $(dirname "$out") does not exist"

if [[ -z $clothbake ]]; then
  clothbake=$repo_root/build/baker/clothbake
  [[ -x $clothbake ]] || clothbake=$repo_root/build/clothbake
fi
[[ $clothbake == */* ]] && clothbake=$(abs "$clothbake")
[[ -x $clothbake ]] || command -v "$clothbake" >/dev/null 2>&1 ||
  say "submit.sh: warning: --clothbake $clothbake is not an executable here; it must be one on the nodes"

if [[ -z $logs ]]; then logs=$out.logs; fi
logs=$(abs "$logs")
[[ -d $logs ]] || made_logs=$logs
mkdir -p "$logs" || die "--logs: cannot create $logs"

# The options after --, NUL-separated, and --threads C unless they name it.
passthrough_and_threads() {
  local o named=0
  for o in "${passthrough[@]}"; do
    printf '%s\0' "$o"
    [[ $o == --threads || $o == --threads=* ]] && named=1
  done
  ((named)) || printf '%s\0' --threads "$cpus"
}

command -v sbatch >/dev/null 2>&1 ||
  die "sbatch not found (install slurm-client; on this machine: scripts/farm/local-cluster.sh start)"

# --- the task files ----------------------------------------------------------
stamp=$(date +%Y%m%d-%H%M%S)-$$
task_dir=$logs/tasks-$stamp
mkdir -p "$task_dir"
made_tasks=$task_dir

write_task() {  # name out [require=...]... -- argv...
  local name=$1 o=$2
  shift 2
  {
    printf 'out=%s\0retries=%s\0' "$o" "$retries"
    while (($# > 0)) && [[ $1 != -- ]]; do
      printf 'require=%s\0' "$1"
      shift
    done
    printf '%s\0' "$@"
  } >"$task_dir/$name.args"
}

job_base=$(basename "$out" | tr -c 'A-Za-z0-9._\n-' '_')
sbatch_common=(--parsable --requeue --open-mode=append --cpus-per-task="$cpus")
[[ -n $partition ]] && sbatch_common+=(--partition="$partition")
[[ -n $account ]] && sbatch_common+=(--account="$account")
[[ -n $time_limit ]] && sbatch_common+=(--time="$time_limit")
[[ -n $mem ]] && sbatch_common+=(--mem="$mem")

submit() {  # sbatch arguments...; prints the job id
  local id
  id=$(sbatch "${sbatch_common[@]}" "$@") || die "sbatch failed: sbatch $(printf '%q ' "${sbatch_common[@]}" "$@")"
  echo "${id%%;*}"
}

array_job="" merge_job="" task_names=() task_outs=()

# One task's input made absolute and named by its file (without the
# extension): `input_path` and `input_name`, refused when missing or when an
# earlier input of this submission had the name (their outputs would collide).
declare -A taken_names=()
name_input() {  # what ("material: spec", "frames: scene"), path as given
  input_path=$(abs "$2")
  [[ -f $input_path ]] || die "${1%%:*}: $2: no such file"
  input_name=$(basename "$input_path")
  input_name=${input_name%.*}
  [[ -z ${taken_names[$input_name]:-} ]] ||
    die "${1%%:*}: two ${1#*: }s named $input_name: their outputs would collide in $out"
  taken_names[$input_name]=1
}

# A library: several specs, one task each, OUTDIR/<spec name>/ (no shards, no merge).
submit_library() {
  [[ -z $shards || $shards == 1 ]] ||
    die "--shards: a library of ${#inputs[@]} specs bakes each whole in one task (--shards 1 or none)"
  [[ -z $range ]] || die "--range: only for frames"
  local opts=() o i
  mapfile -d '' opts < <(passthrough_and_threads)
  for ((i = 1; i <= ${#inputs[@]}; i++)); do
    name_input "material: spec" "${inputs[i - 1]}"
    o=$out/$input_name
    write_task "$i" "$o" -- "$clothbake" material "$input_path" -o "$o" "${opts[@]}" --quiet
    task_names+=("$i")
    task_outs+=("$o")
  done
  mkdir -p "$out"
  array_job=$(submit --array="1-${#inputs[@]}" --job-name="cb-material-$job_base" \
    --output="$logs/%x-%A_%a.out" "$farm_dir/task.sh" "$task_dir")
  submitted=1
  say "material library: ${#inputs[@]} specs, array job $array_job -> $out/<spec name>/"
}

submit_sharded() {  # the material and bake routes
  if [[ $kind == material ]] && ((${#inputs[@]} > 1)); then
    submit_library
    return
  fi
  ((${#inputs[@]} == 1)) || die "$kind: expected one input (scene JSON), got ${#inputs[@]}"
  [[ -n $shards ]] || die "--shards: missing (how many tasks)"
  whole_number --shards "$shards" 1
  [[ -z $range ]] || die "--range: only for frames"
  local input parts i part_list=()
  input=$(abs "${inputs[0]}")
  [[ -f $input ]] || die "$kind: ${inputs[0]}: no such file"
  local opts=()
  mapfile -d '' opts < <(passthrough_and_threads)
  if ((shards == 1)); then
    # One task: the whole bake straight into DIR (a merge takes parts only).
    write_task 1 "$out" -- "$clothbake" "$kind" "$input" -o "$out" "${opts[@]}" --quiet
    task_names+=(1)
    task_outs+=("$out")
    array_job=$(submit --array=1-1 --job-name="cb-$kind-$job_base" \
      --output="$logs/%x-%A_%a.out" "$farm_dir/task.sh" "$task_dir")
    submitted=1
    say "$kind: 1 task, array job $array_job -> $out (no merge)"
    return
  fi
  parts=$out.parts
  mkdir -p "$parts"
  # The parts of an earlier submission for this output: not this run's.
  rm -rf -- "$parts"/part-*
  for ((i = 1; i <= shards; i++)); do
    write_task "$i" "$parts/part-$i" -- \
      "$clothbake" "$kind" "$input" -o "$parts/part-$i" --shard "$i/$shards" "${opts[@]}" --quiet
    part_list+=("$parts/part-$i")
    task_names+=("$i")
    task_outs+=("$parts/part-$i")
  done
  write_task merge "$out" "${part_list[@]}" -- "$clothbake" merge "${part_list[@]}" -o "$out"
  array_job=$(submit --array="1-$shards" --job-name="cb-$kind-$job_base" \
    --output="$logs/%x-%A_%a.out" "$farm_dir/task.sh" "$task_dir")
  submitted=1
  merge_job=$(submit --dependency="afterok:$array_job" --kill-on-invalid-dep=yes \
    --job-name="cb-merge-$job_base" --output="$logs/%x-%j.out" "$farm_dir/task.sh" "$task_dir" merge)
  say "$kind: $shards tasks, array job $array_job -> $parts/part-1..$shards"
  say "merge: job $merge_job (after every task succeeded) -> $out"
}

submit_frames() {
  ((${#inputs[@]} >= 1)) || die "frames: expected scene JSONs or a PATTERN with --range"
  [[ -z $shards ]] || die "--shards: not for frames (one task per frame)"
  local scenes=() i a b
  if [[ -n $range ]]; then
    ((${#inputs[@]} == 1)) || die "--range: expected one PATTERN, got ${#inputs[@]} inputs"
    [[ $range =~ ^([0-9]+)-([0-9]+)$ ]] || die "--range: expected A-B, got '$range'"
    a=$((10#${BASH_REMATCH[1]})) b=$((10#${BASH_REMATCH[2]}))
    ((a <= b)) || die "--range: expected A <= B, got '$range'"
    [[ ${inputs[0]} == *%*d* ]] || die "frames: ${inputs[0]}: a PATTERN needs a printf number (%d, %04d)"
    for ((i = a; i <= b; i++)); do
      # shellcheck disable=SC2059  # the pattern is the format
      scenes+=("$(printf "${inputs[0]}" "$i")")
    done
  else
    scenes=("${inputs[@]}")
  fi
  case $route in
    reference) ;;
    lookup | blender)
      [[ -n $material_dir ]] || die "--material: missing (route $route renders from a material or bake folder)"
      material_dir=$(abs "$material_dir")
      [[ -f $material_dir/manifest.json ]] || die "--material: $material_dir has no manifest.json"
      ;;
    *) die "--route: expected reference, lookup or blender, got '$route'" ;;
  esac
  [[ -z $material_dir || $route != reference ]] || die "--material: only for --route lookup or blender"
  local opts=() scene o
  mapfile -d '' opts < <(passthrough_and_threads)
  for ((i = 1; i <= ${#scenes[@]}; i++)); do
    name_input "frames: scene" "${scenes[i - 1]}"
    scene=$input_path
    o=$out/$input_name.exr
    case $route in
      reference) write_task "$i" "$o" -- "$clothbake" render "$scene" -o "$o" "${opts[@]}" --quiet ;;
      lookup) write_task "$i" "$o" -- "$clothbake" lookup-render "$scene" "$material_dir" -o "$o" "${opts[@]}" --quiet ;;
      blender)
        write_task "$i" "$o" -- "$blender" -b --factory-startup --python-exit-code 1 \
          -P "$(abs "$source_dir")/blender_addon/headless_render.py" -- "$scene" "$material_dir" "$o" "${opts[@]}"
        ;;
    esac
    task_names+=("$i")
    task_outs+=("$o")
  done
  mkdir -p "$out"
  array_job=$(submit --array="1-${#scenes[@]}" --job-name="cb-frames-$job_base" \
    --output="$logs/%x-%A_%a.out" "$farm_dir/task.sh" "$task_dir")
  submitted=1
  say "frames: ${#scenes[@]} tasks (route $route), array job $array_job -> $out/"
}

case $kind in
  material | bake) submit_sharded ;;
  frames) submit_frames ;;
esac
say "logs: $logs/ (task files and status: $task_dir/)"
echo "$array_job${merge_job:+ $merge_job}"
((wait)) || exit 0

# --- --wait: progress, then the summary ----------------------------------------
ids=$array_job${merge_job:+,$merge_job}
n=${#task_names[@]}
finished_state() { [[ $1 =~ ^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY|BOOT_FAIL|DEADLINE|PREEMPTED|SPECIAL_EXIT)$ ]]; }
declare -A state=()
last=""
while :; do
  # Every task and the merge, pending ones listed one by one; a job already
  # purged from slurmctld's memory keeps the state last seen.
  while IFS='|' read -r id st; do
    [[ -n $id ]] && state[$id]=$st
  done < <(squeue -h -r -t all -j "$ids" -o '%i|%T' 2>/dev/null || true)
  done_n=0 failed_n=0 running_n=0 active=0
  for ((i = 1; i <= n; i++)); do
    st=${state[${array_job}_$i]:-PENDING}
    case $st in
      COMPLETED) done_n=$((done_n + 1)) ;;
      RUNNING | COMPLETING) running_n=$((running_n + 1)) ;;
    esac
    if finished_state "$st"; then
      [[ $st == COMPLETED ]] || failed_n=$((failed_n + 1))
    else
      active=1
    fi
  done
  line="$kind: $done_n/$n tasks done, $running_n running"
  ((failed_n)) && line+=", $failed_n failed"
  if [[ -n $merge_job ]]; then
    st=${state[$merge_job]:-PENDING}
    finished_state "$st" || active=1
    line+="; merge ${st,,}"
  fi
  [[ $line != "$last" ]] && say "$line"
  last=$line
  ((active)) || break
  sleep "${CLOTHBAKE_FARM_POLL:-3}"
done

# The summary: scontrol while slurmctld still holds the jobs, else sacct.
declare -A info=()
while read -r line; do
  id=$(grep -o 'JobId=[0-9]*' <<<"$line" | cut -d= -f2)
  task=$(grep -o 'ArrayTaskId=[0-9]*' <<<"$line" | cut -d= -f2 || true)
  [[ -n $task ]] && id=${array_job}_$task
  info[$id]=$line
done < <(scontrol -o show job "$array_job" 2>/dev/null; [[ -z $merge_job ]] || scontrol -o show job "$merge_job" 2>/dev/null)
field() { grep -o " $1=[^ ]*" <<<"$2" | head -1 | cut -d= -f2- || true; }
attempts() { [[ -f $task_dir/status/$1 ]] && wc -l <"$task_dir/status/$1" || echo 0; }
row() {  # id name log
  local l=${info[$1]:-} st ex rt node reason
  if [[ -n $l ]]; then
    st=$(field JobState "$l") ex=$(field ExitCode "$l") rt=$(field RunTime "$l") node=$(field NodeList "$l")
    [[ $(field StartTime "$l") == Unknown ]] && rt=- node=-
    reason=$(field Reason "$l")
    [[ $st == COMPLETED || $reason == None ]] && reason=""
  else
    IFS='|' read -r st ex rt node < <(sacct -X -n -P -j "$1" -o State,ExitCode,Elapsed,NodeList 2>/dev/null | head -1) || true
    st=${st:-${state[$1]:-UNKNOWN}}
  fi
  printf '%-8s %-11s %-6s %-10s %-8s %-10s %s%s\n' "$2" "${st:-?}" "${ex:-?}" "${rt:-?}" \
    "$(attempts "$2")" "${node:-?}" "$3" "${reason:+  (reason: $reason)}"
}
echo
printf '%-8s %-11s %-6s %-10s %-8s %-10s %s\n' task state exit elapsed attempts node log
failed=0
for ((i = 1; i <= n; i++)); do
  id=${array_job}_$i
  row "$id" "$i" "$logs/cb-$kind-$job_base-${array_job}_$i.out"
  [[ ${state[$id]:-} == COMPLETED ]] || failed=1
done
if [[ -n $merge_job ]]; then
  row "$merge_job" merge "$logs/cb-merge-$job_base-$merge_job.out"
  [[ ${state[$merge_job]:-} == COMPLETED ]] || failed=1
fi
echo
if ((failed)); then
  say "submit.sh: some tasks did not complete: see the logs above; $out is as it was before unless the merge completed"
  exit 1
fi
case $kind in
  frames) say "done: ${#task_outs[@]} frames in $out/" ;;
  *) say "done: $out" ;;
esac
