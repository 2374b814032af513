#!/bin/sh
# Start a one-node Slurm cluster on this machine (Debian's slurm-wlm), for .ci/run and for
# trying docs/cluster.md's recipe. Needs root. Everything lives under $PW_SLURM (default
# /tmp/printwatt-slurm): its own slurm.conf (SLURM_CONF points there), spool, state and logs;
# the system's /etc/slurm is not touched. Idempotent: a running cluster is left alone.
# Prints the `export SLURM_CONF=...` line to use.
set -eu
D=${PW_SLURM:-/tmp/printwatt-slurm}
mkdir -p "$D/spool" "$D/state" "$D/log"
HOST=$(hostname -s)
CPUS=$(nproc)
cat > "$D/slurm.conf" <<CONF
ClusterName=printwatt
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmdSpoolDir=$D/spool
StateSaveLocation=$D/state
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
NodeName=$HOST CPUs=$CPUS State=UNKNOWN
PartitionName=printwatt Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$D/slurm.conf"
# munge: the key Debian's package made, or a new one.
if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null
fi
chown munge:munge /etc/munge/munge.key 2>/dev/null || true
chmod 400 /etc/munge/munge.key
mkdir -p /run/munge && chown munge:munge /run/munge 2>/dev/null || true
if ! pgrep -x munged >/dev/null; then
    if id munge >/dev/null 2>&1; then
        su -s /bin/sh munge -c /usr/sbin/munged || /usr/sbin/munged --force
    else
        /usr/sbin/munged --force
    fi
fi
pgrep -x slurmctld >/dev/null || slurmctld
pgrep -x slurmd >/dev/null || slurmd
i=0
until sinfo -h -o '%t' 2>/dev/null | grep -Eq '^(idle|mix|alloc)'; do
    i=$((i + 1))
    if [ $i -gt 60 ]; then
        echo "slurm-local: the node did not come up; logs in $D/log" >&2
        sinfo >&2 || true
        tail -n 20 "$D/log/slurmctld.log" "$D/log/slurmd.log" >&2 || true
        exit 1
    fi
    sleep 1
done
echo "export SLURM_CONF=$D/slurm.conf"
