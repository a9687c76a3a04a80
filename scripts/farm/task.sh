#!/usr/bin/env bash
# One task of a farm job (docs/guide/farm.md): the batch script scripts/farm/submit.sh
# hands to sbatch. Not run by hand.
#   task.sh TASK_DIR [NAME]
# NAME is the task's file in TASK_DIR (default: $SLURM_ARRAY_TASK_ID): NAME.args
# holds NUL-separated fields
#   out=PATH          the output this task publishes (folder or file)
#   require=PATH      a part folder that must exist first (0 or more; the merge)
#   retries=R         how many times a failed attempt is requeued
#   --                then the command, program first
# The task removes stale temporary siblings of its output (left by a killed
# attempt), runs the command, appends a line to TASK_DIR/status/NAME, and on
# failure requeues itself while SLURM_RESTART_COUNT < R.
# Test hook, CLOTHBAKE_FARM_FAULT (comma-separated; NAME is a task's number
# or "merge"):
#   kill:NAME         first attempt only: the program writes its output under
#                     the temporary name, then is killed with SIGKILL before
#                     the rename (it waits there: CLOTHBAKE_TEST_HOLD_UNFINISHED)
#   fail:NAME         every attempt exits 1 without running the program
#   hold:NAME:SECONDS the program waits SECONDS before publishing (to cancel it there)
set -euo pipefail

task_dir=${1:?usage: task.sh TASK_DIR [NAME]}
name=${2:-${SLURM_ARRAY_TASK_ID:-}}
[[ -n $name ]] || {
  echo "task.sh: error: no task name and no SLURM_ARRAY_TASK_ID" >&2
  exit 2
}
args_file=$task_dir/$name.args
[[ -r $args_file ]] || {
  echo "task.sh: error: $args_file: missing or unreadable (TASK_DIR must be on a file system the nodes share)" >&2
  exit 2
}

out="" retries=0 requires=() argv=()
mapfile -d '' fields <"$args_file"
for ((k = 0; k < ${#fields[@]}; k++)); do
  f=${fields[k]}
  case $f in
    out=*) out=${f#out=} ;;
    require=*) requires+=("${f#require=}") ;;
    retries=*) retries=${f#retries=} ;;
    --)
      argv=("${fields[@]:k+1}")
      break
      ;;
    *)
      echo "task.sh: error: $args_file: unknown field '$f'" >&2
      exit 2
      ;;
  esac
done
((${#argv[@]} > 0)) || {
  echo "task.sh: error: $args_file: no command" >&2
  exit 2
}

attempt=${SLURM_RESTART_COUNT:-0}
job=${SLURM_ARRAY_JOB_ID:+${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}}
job=${job:-${SLURM_JOB_ID:-none}}
host=$(hostname -s)
mkdir -p "$task_dir/status"

note() { printf '[farm %s] %s\n' "$(date +%H:%M:%S)" "$*"; }
note "task $name (job $job) attempt $((attempt + 1)) of $((retries + 1)) on $host"
note "command: $(printf '%q ' "${argv[@]}")"

# The faults asked of this task and attempt.
fault_kill=0 fault_fail=0 hold=""
IFS=',' read -r -a faults <<<"${CLOTHBAKE_FARM_FAULT:-}"
for f in "${faults[@]}"; do
  case $f in
    "kill:$name") ((attempt == 0)) && fault_kill=1 ;;
    "fail:$name") fault_fail=1 ;;
    "hold:$name:"*) hold=${f#"hold:$name:"} ;;
  esac
done

# Stale temporaries of this output from a killed attempt: a folder's
# NAME.tmp-PID (and NAME.old-PID once NAME is there, baker/io/atomic_file.h),
# a file's .STEM.tmpPID-N.EXT (clothbake) or .NAME.tmp-PID.exr (Blender).
remove_stale_temporaries() {
  local dir base stem ext p
  dir=$(dirname -- "$out")
  base=$(basename -- "$out")
  stem=${base%.*}
  ext=""
  [[ $base == *.* ]] && ext=.${base##*.}
  shopt -s nullglob
  local stale=("$out".tmp-* "$dir/.$stem.tmp"*"$ext" "$dir/.$base.tmp-"*)
  [[ -e $out ]] && stale+=("$out".old-*)
  shopt -u nullglob
  for p in "${stale[@]}"; do
    rm -rf -- "$p"
    note "removed stale temporary $p"
  done
}

record() {  # state exit seconds
  printf 'attempt=%s state=%s exit=%s seconds=%s host=%s job=%s end=%s\n' \
    $((attempt + 1)) "$1" "$2" "$3" "$host" "$job" "$(date -Is)" >>"$task_dir/status/$name"
}

# Runs the program held before its rename, and SIGKILLs it there.
run_and_kill_before_rename() {
  local err=$task_dir/status/$name.fault-stderr pid i
  CLOTHBAKE_TEST_HOLD_UNFINISHED=300 "${argv[@]}" 2>"$err" &
  pid=$!
  for ((i = 0; i < 6000; i++)); do
    grep -q 'holding unfinished' "$err" 2>/dev/null && break
    [[ -e /proc/$pid ]] || break
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  local rc=0
  wait "$pid" || rc=$?
  cat "$err" >&2
  note "fault injected (CLOTHBAKE_FARM_FAULT): killed pid $pid with SIGKILL before its rename; left:" \
    "$(cd "$(dirname -- "$out")" && ls -d -- "$(basename -- "$out")"* 2>/dev/null | tr '\n' ' ')"
  return "$rc"
}

start_ns=$(date +%s%N)
rc=0
missing=()
for r in "${requires[@]}"; do
  [[ -d $r && -f $r/manifest.json ]] || missing+=("$r")
done
if ((${#missing[@]} > 0)); then
  echo "task.sh: error: task $name: ${#missing[@]} part(s) missing, not merging: ${missing[*]}" >&2
  rc=3
elif ((fault_fail)); then
  note "fault injected (CLOTHBAKE_FARM_FAULT): failing without running"
  rc=1
else
  remove_stale_temporaries
  if ((fault_kill)); then
    run_and_kill_before_rename || rc=$?
  elif [[ -n $hold ]]; then
    CLOTHBAKE_TEST_HOLD_UNFINISHED=$hold "${argv[@]}" || rc=$?
  else
    "${argv[@]}" || rc=$?
  fi
fi
# Milliseconds: the scaling figure (lab/farm_scaling/scaling.sh) reads these.
end_ns=$(date +%s%N)
seconds=$(printf '%d.%03d' $(((end_ns - start_ns) / 1000000000)) $((((end_ns - start_ns) / 1000000) % 1000)))

if ((rc == 0)); then
  record "done" 0 "$seconds"
  note "task $name done in $seconds s: $out"
  exit 0
fi
if ((attempt < retries)) && [[ -n ${SLURM_JOB_ID:-} ]]; then
  record requeued "$rc" "$seconds"
  note "task $name failed (exit $rc) after $seconds s: requeueing (attempt $((attempt + 1)) of $((retries + 1)))"
  # The array task by its array name; a lone job (the merge) by its id.
  target=${SLURM_ARRAY_JOB_ID:+${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}}
  if scontrol requeue "${target:-$SLURM_JOB_ID}"; then
    exit "$rc"
  fi
  note "scontrol requeue ${target:-$SLURM_JOB_ID} failed: the task stays failed"
fi
record failed "$rc" "$seconds"
note "task $name failed (exit $rc) after $seconds s, attempt $((attempt + 1)) of $((retries + 1)): giving up"
exit "$rc"
