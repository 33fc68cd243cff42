#!/usr/bin/env bash
# slurm-local.sh install|start|stop|env [DIR]: a one-node Slurm cluster on this machine, from
# Debian's packages, for `plugslam sweep run --engine slurm` and its tests. No systemd: munged,
# slurmctld and slurmd run from DIR (default /tmp/plugslam-slurm-$UID) with their own munge key,
# state folders and ports (16817/16818, so a system Slurm is never touched), and stop by pid.
#   install      installs slurmctld slurmd slurm-client munge if missing (scripts/apt-install.sh)
#   start        install, then start the daemons and wait until the node is idle; prints the
#                `export SLURM_CONF=...` line the client commands (sbatch, squeue) need
#   stop         cancels the cluster's jobs, stops the daemons by pid
#   env          prints the export line
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cmd="${1:-}"
dir="${2:-${PLUGSLAM_SLURM_DIR:-/tmp/plugslam-slurm-$(id -u)}}"
conf="$dir/slurm.conf"
export SLURM_CONF="$conf"

install() {
  local missing=()
  for p in slurmctld slurmd slurm-client munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] || "$here/apt-install.sh" slurm-local.sh "${missing[@]}"
}

# Stops the process whose pid a file holds, if it still runs: TERM, then KILL after 5 s.
stop_pid() {
  local file="$1" pid
  [ -s "$file" ] || return 0
  pid="$(cat "$file")"
  if kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

stop() {
  if [ -f "$conf" ] && [ -s "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
    scancel --quiet --full "$(squeue -h -o %A 2>/dev/null | tr '\n' ' ')" 2>/dev/null || true
  fi
  stop_pid "$dir/slurmd.pid"
  stop_pid "$dir/slurmctld.pid"
  stop_pid "$dir/munged.pid"
}

start() {
  install
  # A cluster left from an earlier start is stopped first: one set of daemons per folder.
  stop
  local host cpus
  host="$(hostname -s)"
  cpus="$(nproc)"
  mkdir -p "$dir"/{state,spool,log,munge,munge-key}
  chmod 755 "$dir/munge"  # 700 makes the socket inaccessible to users other than root
  chmod 700 "$dir/munge-key"
  if [ ! -s "$dir/munge-key/munge.key" ]; then
    dd if=/dev/urandom of="$dir/munge-key/munge.key" bs=1 count=1024 status=none
    chmod 400 "$dir/munge-key/munge.key"
  fi
  cat > "$conf" <<EOF
ClusterName=plugslam
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=300
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  munged -F -f --key-file="$dir/munge-key/munge.key" --socket="$dir/munge/munge.sock" \
    --pid-file="$dir/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed" \
    > "$dir/log/munged.out" 2>&1 &
  echo $! > "$dir/munged.pid"
  for _ in $(seq 50); do [ -S "$dir/munge/munge.sock" ] && break; sleep 0.1; done
  [ -S "$dir/munge/munge.sock" ] || { echo "slurm-local.sh: munged did not start: $(tail -3 "$dir/log/munged.log" 2>/dev/null)" >&2; exit 1; }
  slurmctld -D -i -f "$conf" > "$dir/log/slurmctld.out" 2>&1 &
  echo $! > "$dir/slurmctld.pid"
  slurmd -D -f "$conf" > "$dir/log/slurmd.out" 2>&1 &
  echo $! > "$dir/slurmd.pid"
  local state=""
  for _ in $(seq 300); do
    state="$(sinfo -h -o %t 2>/dev/null || true)"
    [ "$state" = idle ] && break
    sleep 0.1
  done
  if [ "$state" != idle ]; then
    echo "slurm-local.sh: the node is not idle after 30 s (state '$state'); logs in $dir/log" >&2
    tail -5 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 2>/dev/null || true
    stop
    exit 1
  fi
  echo "slurm-local.sh: one-node cluster up ($host, $cpus CPUs, partition local)"
  echo "export SLURM_CONF=$conf"
}

case "$cmd" in
  install) install ;;
  start) start ;;
  stop) stop ;;
  env) echo "export SLURM_CONF=$conf" ;;
  *) echo "usage: $0 install|start|stop|env [DIR]" >&2; exit 2 ;;
esac
