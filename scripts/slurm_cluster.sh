#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the farm tests and for trying
# `kdray farm` without a real cluster. Uses Debian's packages
# (slurmctld slurmd slurm-client munge); needs root (slurmd runs jobs as
# their submitter) and no systemd.
#
#   scripts/slurm_cluster.sh start DIR   # writes DIR/slurm.conf, starts munged,
#                                        # slurmctld and slurmd, waits for the node
#   scripts/slurm_cluster.sh stop DIR    # stops what start started, by pid
#
# After `start`, `export SLURM_CONF=DIR/slurm.conf` points sbatch, squeue and
# sinfo at it. Ports: SLURM_CLUSTER_PORT (default 6817) for slurmctld and the
# next one for slurmd.
set -euo pipefail

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
cmd=$1
dir=$(realpath -m "$2")

stop_pid_file() {
    local f=$1
    [ -s "$f" ] || return 0
    local pid
    pid=$(cat "$f")
    if kill -0 "$pid" 2>/dev/null; then
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$f"
}

case "$cmd" in
start)
    for tool in slurmctld slurmd sinfo munged; do
        command -v "$tool" >/dev/null || {
            echo "$0: $tool not found: apt-get install --no-install-recommends slurmctld slurmd slurm-client munge" >&2
            exit 1
        }
    done
    port=${SLURM_CLUSTER_PORT:-6817}
    mkdir -p "$dir/state" "$dir/spool" "$dir/log"
    node=$(hostname -s)
    # The node's CPUs, sockets and cores as slurmd sees them; RealMemory left
    # out so that jobs are not refused for memory the VM reports differently.
    hw=$(slurmd -C | head -1 | sed -e 's/^NodeName=[^ ]* //' -e 's/ RealMemory=[0-9]*//')
    cat > "$dir/slurm.conf" <<CONF
ClusterName=kdray
SlurmctldHost=$node
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
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
SchedulerParameters=batch_sched_delay=0
EnforcePartLimits=ALL
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
NodeName=$node $hw State=UNKNOWN
PartitionName=main Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
    # munged: one per machine; started here only if none answers.
    if ! munge -n </dev/null >/dev/null 2>&1; then
        install -d -o munge -g munge /run/munge "$dir/munge"
        runuser -u munge -- /usr/sbin/munged --pid-file="$dir/munge/munged.pid" 2>"$dir/log/munged.err" \
            || { echo "$0: munged did not start: $(cat "$dir/log/munged.err")" >&2; exit 1; }
    fi
    slurmctld -f "$dir/slurm.conf" -i || { echo "$0: slurmctld did not start; logs in $dir/log" >&2; "$0" stop "$dir"; exit 1; }
    slurmd -f "$dir/slurm.conf" || { echo "$0: slurmd did not start; logs in $dir/log" >&2; "$0" stop "$dir"; exit 1; }
    export SLURM_CONF=$dir/slurm.conf
    for _ in $(seq 100); do
        state=$(sinfo -h -N -o '%t' 2>/dev/null | head -1 || true)
        case "$state" in idle|mix|alloc) echo "slurm cluster up: export SLURM_CONF=$dir/slurm.conf"; exit 0;; esac
        sleep 0.2
    done
    echo "$0: the node did not become idle in 20 s (state '${state:-none}'); logs in $dir/log" >&2
    "$0" stop "$dir" || true
    exit 1
    ;;
stop)
    stop_pid_file "$dir/slurmd.pid"
    stop_pid_file "$dir/slurmctld.pid"
    stop_pid_file "$dir/munge/munged.pid"
    ;;
*) usage ;;
esac
