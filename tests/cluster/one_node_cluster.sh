#!/usr/bin/env bash
# A one-node Slurm cluster on this machine for tests: munge and slurmctld and slurmd from Debian,
# on loopback, with their state, spool, logs and configuration in DIR.
#   one_node_cluster.sh start DIR   starts the daemons (and munged if none runs); prints SLURM_CONF
#   one_node_cluster.sh stop DIR    stops what start started
# start exits non-zero, with the reason on stderr, where the daemons cannot start (not root, no
# packages, no munge key): the tests then skip with that reason.
set -euo pipefail

command=${1:-}
dir=${2:-}
if [ -z "$command" ] || [ -z "$dir" ]; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi

stop_pid_file() {
  local file=$1
  if [ -f "$file" ]; then
    local pid
    pid=$(cat "$file")
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -9 "$pid" 2>/dev/null || true
    rm -f "$file"
  fi
}

if [ "$command" = stop ]; then
  stop_pid_file "$dir/slurmd.pid"
  stop_pid_file "$dir/slurmctld.pid"
  if [ -f "$dir/munged.started" ]; then
    stop_pid_file /run/munge/munged.pid
    rm -f "$dir/munged.started"
  fi
  exit 0
fi

[ "$command" = start ] || { echo "unknown command $command" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || { echo "needs root to run munged and slurmd" >&2; exit 1; }
for program in munged munge unmunge slurmctld slurmd sinfo sbatch squeue; do
  command -v "$program" >/dev/null || [ -x "/usr/sbin/$program" ] ||
    { echo "$program is not installed (scripts/install-deps installs it)" >&2; exit 1; }
done
[ -r /etc/munge/munge.key ] || { echo "no /etc/munge/munge.key" >&2; exit 1; }
mkdir -p "$dir/state" "$dir/spool"
dir=$(cd "$dir" && pwd)

# munge: its socket folder and log belong to the munge user
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge
  runuser -u munge -- /usr/sbin/munged
  touch "$dir/munged.started"
  for _ in $(seq 50); do
    munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break
    sleep 0.1
  done
  munge -n | unmunge >/dev/null || { echo "munged does not authenticate" >&2; exit 1; }
fi

host=$(hostname -s)
cpus=$(nproc)
memory_mb=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))
# ports of our own, so that no other Slurm on the machine clashes
base_port=$(( 17000 + ($$ % 1000) * 2 ))
cat > "$dir/slurm.conf" <<CONF
ClusterName=trav-test
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
SlurmctldPort=$base_port
SlurmdPort=$(( base_port + 1 ))
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SchedulerType=sched/backfill
NodeName=$host CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF

/usr/sbin/slurmctld -f "$dir/slurm.conf"
/usr/sbin/slurmd -f "$dir/slurm.conf"
export SLURM_CONF="$dir/slurm.conf"
for _ in $(seq 100); do
  if sinfo -h -o %t 2>/dev/null | grep -qE 'idle|mix|alloc'; then
    echo "$SLURM_CONF"
    exit 0
  fi
  sleep 0.2
done
echo "the node did not come up (see $dir/slurmctld.log and $dir/slurmd.log)" >&2
sinfo >&2 || true
exit 1
