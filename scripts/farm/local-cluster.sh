#!/usr/bin/env bash
# A one-machine Slurm cluster for the farm scripts (docs/guide/farm.md): munged,
# slurmctld and one slurmd on this machine, every file of theirs under one
# folder, no systemd, nothing written to /etc/slurm or /etc/munge.
#   scripts/farm/local-cluster.sh start|stop|status|env|purge
#     start   write the configuration if missing, start whatever daemon is not
#             running, wait (bounded) until the node takes jobs; idempotent
#     stop    cancel this cluster's jobs, stop the three daemons; idempotent
#     status  each daemon up or down, then sinfo
#     env     the line clients need: eval "$(scripts/farm/local-cluster.sh env)"
#     purge   stop, then delete the folder
# The folder: $CLOTHBAKE_CLUSTER_DIR, default /tmp/clothbake-cluster:
#   etc/slurm.conf  munge/{munge.key,munge.socket.2,munged.seed}  run/*.pid
#   log/{munged,slurmctld,slurmd}.log, log/jobcomp.txt  spool/  state/
# Ports: two free ones from 16817 up, picked when slurm.conf is written and
# kept in it (a second cluster in another folder picks others).
# Tested as root (Debian 12, slurm-wlm 22.05, in a container without systemd
# or cgroups): jobs run as the user that started the cluster.
set -euo pipefail

cluster_dir=${CLOTHBAKE_CLUSTER_DIR:-/tmp/clothbake-cluster}
conf=$cluster_dir/etc/slurm.conf
munge_socket=$cluster_dir/munge/munge.socket.2
node=$(hostname -s)
wait_seconds=${CLOTHBAKE_CLUSTER_WAIT:-60}
export SLURM_CONF=$conf

say() { printf '[local-cluster] %s\n' "$*" >&2; }
die() {
  printf 'local-cluster: error: %s\n' "$*" >&2
  exit 1
}

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
}

need() {
  local p
  for p in "$@"; do
    command -v "$p" >/dev/null 2>&1 ||
      die "$p not found: install slurm-wlm and munge (scripts/packages.txt; apt-get install -y --no-install-recommends slurm-wlm munge)"
  done
}

pid_file() { echo "$cluster_dir/run/$1.pid"; }
log_file() { echo "$cluster_dir/log/$1.log"; }

# The daemon's pid if its pid file names a live process of that program.
daemon_pid() {
  local f pid comm
  f=$(pid_file "$1")
  [[ -s $f ]] || return 1
  pid=$(tr -dc '0-9' <"$f")
  [[ -n $pid && -r /proc/$pid/comm ]] || return 1
  comm=$(<"/proc/$pid/comm")
  [[ $comm == "$1"* ]] || return 1
  echo "$pid"
}

log_tail() {
  local f
  f=$(log_file "$1")
  if [[ -s $f ]]; then
    echo "--- last lines of $f:"
    tail -n 20 "$f"
  else
    echo "--- $f is empty or missing"
  fi
}

# Ports listening now (decimal), from /proc/net/tcp{,6}: no tools needed.
listening_ports() {
  local f local_address state _
  for f in /proc/net/tcp /proc/net/tcp6; do
    [[ -r $f ]] || continue
    while read -r _ local_address _ state _; do
      [[ $state == 0A ]] && echo $((16#${local_address##*:}))
    done < <(tail -n +2 "$f")
  done
}

free_port_pair() {
  local used p
  used=" $(listening_ports | tr '\n' ' ') "
  for ((p = 16817; p < 17817; p += 2)); do
    [[ $used == *" $p "* || $used == *" $((p + 1)) "* ]] && continue
    echo "$p"
    return
  done
  die "no two free TCP ports between 16817 and 17817"
}

write_config() {
  mkdir -p "$cluster_dir"/{etc,munge,run,log,spool/slurmd,state}
  # munged wants its socket's folder searchable by all, the key private.
  chmod 755 "$cluster_dir/munge"
  if [[ ! -s $cluster_dir/munge/munge.key ]]; then
    (umask 077 && head -c 1024 /dev/urandom >"$cluster_dir/munge/munge.key")
    say "new munge key $cluster_dir/munge/munge.key"
  fi
  [[ -s $conf ]] && return
  local port cpus mem_mib user
  port=$(free_port_pair)
  cpus=$(nproc)
  # RealMemory a bit under the total, so slurmd never finds less than configured.
  mem_mib=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 * 0.95 }' /proc/meminfo)
  user=$(id -un)
  cat >"$conf.tmp" <<EOF
# Written by scripts/farm/local-cluster.sh for $cluster_dir (clothbake local cluster).
ClusterName=clothbake
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
# cred_expire is also how long a requeued job waits before it may start
# again (default 120 s); short here, so a retried task restarts in seconds.
AuthInfo=socket=$munge_socket,cred_expire=10
StateSaveLocation=$cluster_dir/state
SlurmdSpoolDir=$cluster_dir/spool/slurmd
SlurmctldPidFile=$(pid_file slurmctld)
SlurmdPidFile=$(pid_file slurmd)
SlurmctldLogFile=$(log_file slurmctld)
SlurmdLogFile=$(log_file slurmd)
SlurmctldDebug=info
SlurmdDebug=info
# No systemd, no cgroups: processes tracked through /proc, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/linux
# No slurmdbd: sacct has no accounting to read; finished jobs are kept in
# slurmctld's memory for MinJobAge seconds (scontrol show job) and listed in
# JobCompLoc.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$cluster_dir/log/jobcomp.txt
MinJobAge=600
MailProg=/bin/true
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
# Look at pending jobs every few seconds (a requeued task's wait ends unseen
# until the next pass).
SchedulerParameters=bf_interval=2,sched_interval=2
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
ReturnToService=2
JobRequeue=1
MaxArraySize=10001
MaxJobCount=20000
KillWait=10
InactiveLimit=0
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mib State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$conf.tmp" "$conf"
  say "wrote $conf (ports $port, $((port + 1)); $cpus CPUs, $mem_mib MiB)"
}

# Waits until `check` succeeds, at most $wait_seconds; else dies with the log's tail.
wait_for() {
  local what=$1 log=$2
  shift 2
  local deadline=$((SECONDS + wait_seconds))
  until "$@" >/dev/null 2>&1; do
    ((SECONDS < deadline)) || die "$what not ready after $wait_seconds s
$(log_tail "$log")"
    sleep 0.5
  done
}

munge_works() { munge -n --socket="$munge_socket" | unmunge --socket="$munge_socket"; }
ctld_up() { scontrol ping | grep -q 'is UP'; }
node_state() { sinfo -h -n "$node" -o '%T' 2>/dev/null | head -1; }
node_takes_jobs() {
  # idle, or busy with jobs that survived a restart
  [[ $(node_state) =~ ^(idle|mixed|allocated|completing)$ ]]
}

start_munged() {
  daemon_pid munged >/dev/null && return
  rm -f "$munge_socket" "$munge_socket.lock"
  munged --key-file="$cluster_dir/munge/munge.key" --socket="$munge_socket" \
    --pid-file="$(pid_file munged)" --log-file="$(log_file munged)" \
    --seed-file="$cluster_dir/munge/munged.seed" ||
    die "munged did not start
$(log_tail munged)"
  wait_for munged munged munge_works
  say "munged up (socket $munge_socket)"
}

start_slurmctld() {
  daemon_pid slurmctld >/dev/null && return
  slurmctld || die "slurmctld did not start
$(log_tail slurmctld)"
  wait_for slurmctld slurmctld ctld_up
  say "slurmctld up"
}

start_slurmd() {
  if ! daemon_pid slurmd >/dev/null; then
    slurmd || die "slurmd did not start
$(log_tail slurmd)"
    say "slurmd started"
  fi
  local deadline=$((SECONDS + wait_seconds)) resumed=0 state
  until node_takes_jobs; do
    state=$(node_state)
    # A node left down or drained by an earlier run (killed daemons): resume it once.
    if ((!resumed)) && [[ $state =~ ^(down|drain|drained|draining|fail) ]]; then
      scontrol update nodename="$node" state=resume >/dev/null 2>&1 || true
      resumed=1
    fi
    ((SECONDS < deadline)) || die "node $node is '${state:-unknown}', not idle, after $wait_seconds s
$(scontrol show node "$node" 2>&1 | grep -E 'State|Reason' || true)
$(log_tail slurmd)
$(log_tail slurmctld)"
    sleep 0.5
  done
  say "node $node $(node_state)"
}

# munged refuses a socket below a folder that not all may search.
check_searchable() {
  local d
  d=$(realpath -m "$cluster_dir")
  while [[ $d != / ]]; do
    [[ ! -e $d || $(stat -c %A "$d") == ?????????[xt] ]] ||
      die "$d: munged needs every folder above its socket searchable by all (chmod o+x $d), or another CLOTHBAKE_CLUSTER_DIR"
    d=$(dirname "$d")
  done
}

cmd_start() {
  need munged munge unmunge slurmctld slurmd scontrol sinfo
  check_searchable
  write_config
  start_munged
  start_slurmctld
  start_slurmd
  say "clients: export SLURM_CONF=$conf"
}

stop_daemon() {
  local pid
  pid=$(daemon_pid "$1") || {
    rm -f "$(pid_file "$1")"
    return 0
  }
  kill -TERM "$pid" 2>/dev/null || true
  local i
  for ((i = 0; i < 40; i++)); do
    [[ -e /proc/$pid ]] || break
    sleep 0.25
  done
  if [[ -e /proc/$pid ]]; then
    kill -KILL "$pid" 2>/dev/null || true
    say "$1 (pid $pid) did not stop on SIGTERM in 10 s: killed"
  fi
  rm -f "$(pid_file "$1")"
  say "$1 stopped"
}

cmd_stop() {
  if daemon_pid slurmctld >/dev/null && daemon_pid munged >/dev/null; then
    local jobs
    jobs=$(squeue -h -o '%A' 2>/dev/null | sort -u | tr '\n' ' ')
    if [[ -n ${jobs// /} ]]; then
      say "cancelling jobs: $jobs"
      # shellcheck disable=SC2086  # job ids, one word each
      scancel $jobs 2>/dev/null || true
      local i
      for ((i = 0; i < 60; i++)); do
        [[ -z $(squeue -h -o '%A' 2>/dev/null) ]] && break
        sleep 0.5
      done
    fi
  fi
  stop_daemon slurmd
  stop_daemon slurmctld
  stop_daemon munged
}

cmd_status() {
  local d pid rc=0
  for d in munged slurmctld slurmd; do
    if pid=$(daemon_pid "$d"); then
      printf '%-10s up (pid %s)\n' "$d" "$pid"
    else
      printf '%-10s down\n' "$d"
      rc=3
    fi
  done
  echo "SLURM_CONF=$conf"
  if daemon_pid slurmctld >/dev/null; then
    sinfo || rc=3
  fi
  return $rc
}

cmd_env() {
  printf 'export SLURM_CONF=%q\n' "$conf"
}

cmd_purge() {
  cmd_stop
  [[ -d $cluster_dir ]] || return 0
  # Only a folder this script made.
  grep -q '^# Written by scripts/farm/local-cluster.sh' "$conf" 2>/dev/null ||
    die "$cluster_dir has no slurm.conf written by this script: not deleting it"
  rm -rf "$cluster_dir"
  say "deleted $cluster_dir"
}

case ${1:-} in
  start) cmd_start ;;
  stop) cmd_stop ;;
  status) cmd_status ;;
  env) cmd_env ;;
  purge) cmd_purge ;;
  -h | --help)
    usage
    ;;
  *)
    usage >&2
    die "expected start, stop, status, env or purge, got '${1:-}'"
    ;;
esac
