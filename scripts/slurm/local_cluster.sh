#!/usr/bin/env bash
# A one-node Slurm cluster on loopback, for the end-to-end test of the recipe
# (tests/slurm; docs/production.md#slurm): munged with a generated key, slurmctld and slurmd,
# every file (key, slurm.conf, state, spool, logs, pid files) inside DIR.
#
#   local_cluster.sh install          Debian's slurm-wlm and munge, if missing (root)
#   local_cluster.sh start DIR        start the daemons; prints "export SLURM_CONF=DIR/slurm.conf"
#   local_cluster.sh stop DIR         stop every daemon started with DIR (idempotent)
#
# The daemons run as root (the test's user); nothing outside DIR is written or read, except
# Slurm's plugins. Ports are picked free at start.
set -euo pipefail
cmd="${1:-}"
case "$cmd" in
  install)
    missing=()
    for p in slurm-wlm munge; do
      dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
      [ "$(id -u)" = 0 ] || { echo "local_cluster.sh: installing ${missing[*]} needs root" >&2; exit 77; }
      export DEBIAN_FRONTEND=noninteractive
      apt-get update -qq >/dev/null
      apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    fi
    ;;
  start)
    dir="$(realpath -m "${2:?local_cluster.sh start DIR}")"
    mkdir -p "$dir"/{munge,state,spool,logs}
    chmod 700 "$dir/munge"
    # A fresh key per cluster: 1 KiB of random bytes, readable by its owner only (munged
    # refuses a key others can read).
    head -c 1024 /dev/urandom > "$dir/munge/munge.key"
    chmod 400 "$dir/munge/munge.key"
    munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
      --pid-file="$dir/munge/munged.pid" --log-file="$dir/logs/munged.log" --seed-file="$dir/munge/munged.seed"
    free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
    ctld_port=$(free_port); d_port=$(free_port)
    while [ "$d_port" = "$ctld_port" ]; do d_port=$(free_port); done
    cpus=$(nproc)
    mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
    cat > "$dir/slurm.conf" <<CONF
ClusterName=archwave-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/slurmd-%n
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd-%n.pid
SlurmctldLogFile=$dir/logs/slurmctld.log
SlurmdLogFile=$dir/logs/slurmd-%n.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
LaunchParameters=use_interactive_step
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
PlugStackConfig=$dir/plugstack.conf
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
KillWait=10
NodeName=awnode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=awnode Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE:4
CONF
    : > "$dir/plugstack.conf"
    export SLURM_CONF="$dir/slurm.conf"
    slurmctld -f "$dir/slurm.conf" -i
    slurmd -f "$dir/slurm.conf" -N awnode
    # Up when the node is idle (slurmd registered with slurmctld).
    for _ in $(seq 1 60); do
      if sinfo -h -n awnode -o '%t' 2>/dev/null | grep -q '^idle'; then
        echo "export SLURM_CONF=$dir/slurm.conf"
        exit 0
      fi
      sleep 0.5
    done
    echo "local_cluster.sh: the node did not come up within 30 s; logs in $dir/logs:" >&2
    tail -n 20 "$dir"/logs/*.log >&2 || true
    exit 1
    ;;
  stop)
    dir="$(realpath -m "${2:?local_cluster.sh stop DIR}")"
    for pidfile in "$dir"/slurmd-*.pid "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
      [ -f "$pidfile" ] || continue
      pid=$(cat "$pidfile" 2>/dev/null || true)
      [ -n "$pid" ] && kill "$pid" 2>/dev/null || true
    done
    # Wait for them to go (bounded), then make sure.
    for _ in $(seq 1 20); do
      alive=0
      for pidfile in "$dir"/slurmd-*.pid "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
        [ -f "$pidfile" ] || continue
        pid=$(cat "$pidfile" 2>/dev/null || true)
        [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null && alive=1
      done
      [ $alive = 0 ] && break
      sleep 0.25
    done
    for pidfile in "$dir"/slurmd-*.pid "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
      [ -f "$pidfile" ] || continue
      pid=$(cat "$pidfile" 2>/dev/null || true)
      [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null || true
      rm -f "$pidfile"
    done
    # slurmstepd processes of jobs still running.
    pkill -9 -f "slurmstepd.*$dir" 2>/dev/null || true
    ;;
  *)
    sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac
