#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for the sweep tests and for trying `starnav sweep
# slurm` without a cluster: munged, slurmctld and slurmd on localhost, every file (key, sockets,
# state, logs, slurm.conf) in one folder, no systemd; stopped by the daemons' process ids.
#
#   scripts/slurm-local-cluster.sh start DIR [--max-array-size N]   # prints SLURM_CONF=DIR/slurm.conf
#   export SLURM_CONF=DIR/slurm.conf; sbatch ...; squeue ...
#   scripts/slurm-local-cluster.sh stop DIR
#
# The daemons run in sessions of their own (setsid), so they outlive the shell or the process
# group that started them. Needs Debian's slurm-wlm and munge (scripts/install-deps.sh ci installs them); exits 3 with a
# message naming what is missing. The daemons run as the calling user (the jobs too); slurmd runs
# jobs as other users only when started as root. Ports: two free TCP ports on 127.0.0.1.
set -euo pipefail

usage() {
  echo "usage: $0 start DIR [--max-array-size N] | stop DIR" >&2
  exit 2
}
[ $# -ge 2 ] || usage
action=$1
dir=$2
shift 2
max_array=""
while [ $# -gt 0 ]; do
  case "$1" in
    --max-array-size) max_array=${2:?}; shift 2 ;;
    *) usage ;;
  esac
done
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)

# Stops the daemons whose ids are in DIR/*.pid: TERM to all, then KILL to those still there after 5 s.
stop_cluster() {
  local pids=() f pid i alive
  if [ -f "$dir/slurm.conf" ] && [ -f "$dir/slurmctld.pid" ]; then
    SLURM_CONF="$dir/slurm.conf" timeout 5 scancel --user="$(id -un)" >/dev/null 2>&1 || true
  fi
  for f in slurmd slurmctld munged; do
    [ -f "$dir/$f.pid" ] || continue
    pid=$(cat "$dir/$f.pid")
    rm -f "$dir/$f.pid"
    if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
      kill -TERM "$pid" 2>/dev/null || true
      pids+=("$pid")
    fi
  done
  for i in $(seq 100); do
    alive=()
    for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive+=("$pid"); done
    [ ${#alive[@]} -eq 0 ] && return 0
    sleep 0.05
  done
  kill -KILL "${alive[@]}" 2>/dev/null || true
}

if [ "$action" = stop ]; then
  stop_cluster
  exit 0
fi
[ "$action" = start ] || usage

missing=()
for c in munged mungekey slurmctld slurmd sbatch squeue scontrol sinfo scancel; do
  command -v "$c" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin:/sbin" command -v "$c" >/dev/null 2>&1 || missing+=("$c")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "slurm-local-cluster: missing ${missing[*]} (Debian packages slurm-wlm and munge; scripts/install-deps.sh ci)" >&2
  exit 3
fi
export PATH="$PATH:/usr/sbin:/sbin"

# A TCP port nothing listens on (from /proc/net/tcp*), starting at a value drawn from this process.
port_in_use() {
  local hex
  hex=$(printf '%04X' "$1")
  cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk -v p=":$hex" '$2 ~ p"$" && $4 == "0A" {found=1} END {exit !found}'
}
free_port() {
  local p=$1
  while port_in_use "$p" || [ "$p" = "${2:-0}" ]; do p=$((p + 1)); done
  echo "$p"
}
base=$((20000 + ($$ * 7) % 20000))
ctld_port=$(free_port "$base")
slurmd_port=$(free_port $((ctld_port + 1)) "$ctld_port")

if [ ${#dir} -gt 80 ]; then
  # munged's socket (DIR/munge/munge.socket) must fit in a Unix socket address (108 bytes).
  echo "slurm-local-cluster: $dir: give a shorter folder (at most 80 characters; munge's socket path must fit in 108)" >&2
  exit 2
fi
user=$(id -un)
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
chmod 700 "$dir/munge"
rm -f "$dir/munge/munge.key"
mungekey --create --keyfile="$dir/munge/munge.key"
chmod 600 "$dir/munge/munge.key"
setsid munged --foreground --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" \
  >"$dir/log/munged.out" 2>&1 &
echo $! >"$dir/munged.pid"
for i in $(seq 100); do
  [ -S "$dir/munge/munge.socket" ] && break
  sleep 0.05
done
if [ ! -S "$dir/munge/munge.socket" ]; then
  echo "slurm-local-cluster: munged did not start:" >&2
  tail -5 "$dir/log/munged.out" "$dir/log/munged.log" >&2 2>/dev/null || true
  stop_cluster
  exit 1
fi

cpus=$(nproc)
cat >"$dir/slurm.conf" <<EOF
# A single-node cluster for tests (scripts/slurm-local-cluster.sh).
ClusterName=starnav-local
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.daemon.pid
SlurmdPidFile=$dir/slurmd.daemon.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
MailProg=/bin/true
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=300
SchedulerParameters=sched_interval=1
ReturnToService=2
${max_array:+MaxArraySize=$max_array}
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"
setsid slurmctld -D -c -i >"$dir/log/slurmctld.out" 2>&1 &
echo $! >"$dir/slurmctld.pid"
setsid slurmd -D -N localhost >"$dir/log/slurmd.out" 2>&1 &
echo $! >"$dir/slurmd.pid"

# Up when the node is idle.
state=""
for i in $(seq 200); do
  state=$(sinfo -h -N -o %T 2>/dev/null | head -1 || true)
  [ "$state" = idle ] && break
  sleep 0.1
done
if [ "$state" != idle ]; then
  echo "slurm-local-cluster: the node did not become idle (state '$state'):" >&2
  tail -5 "$dir/log/slurmctld.out" "$dir/log/slurmctld.log" "$dir/log/slurmd.out" "$dir/log/slurmd.log" >&2 2>/dev/null || true
  stop_cluster
  exit 1
fi
echo "SLURM_CONF=$dir/slurm.conf"
