#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying `brdf-sls slurm` and for CI.
#
#   scripts/slurm-local.sh start    install slurm-wlm and munge when missing (apt-get, as root),
#                                   write a minimal config, start munged, slurmctld and slurmd
#   scripts/slurm-local.sh status   the daemons this script started, and `sinfo`
#   scripts/slurm-local.sh stop     stop exactly the daemons this script started (by PID)
#
# Must run as root. The PIDs of the daemons it starts are recorded in $STATE_DIR/pids; `stop`
# kills only those PIDs, never processes found by name (other work may share the machine).
# Daemons that were already running (e.g. a system munged) are used and left alone.
# A slurm.conf that this script did not write is used as it is, never overwritten.
#
# Environment: BRDF_SLS_SLURM_STATE (state folder, default /var/tmp/brdf-sls-slurm).
set -euo pipefail

STATE_DIR=${BRDF_SLS_SLURM_STATE:-/var/tmp/brdf-sls-slurm}
PIDS=$STATE_DIR/pids
CONF=/etc/slurm/slurm.conf
MARKER="# written by brdf-sls scripts/slurm-local.sh"

say() { printf 'slurm-local: %s\n' "$*" >&2; }
die() { say "error: $*"; exit 1; }

need_root() {
    [ "$(id -u)" = 0 ] || die "must run as root (it installs packages and starts daemons)"
}

install_packages() {
    if command -v slurmctld >/dev/null && command -v slurmd >/dev/null \
        && command -v sbatch >/dev/null && command -v munged >/dev/null; then
        return
    fi
    say "installing slurm-wlm and munge (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >/dev/null
    apt-get install -y -q --no-install-recommends slurm-wlm munge >/dev/null
}

# Waits up to $2 seconds for file $1 to exist and hold a PID; prints the PID.
wait_pidfile() {
    local file=$1 secs=$2 i pid
    for ((i = 0; i < secs * 10; i++)); do
        if [ -s "$file" ]; then
            pid=$(tr -dc '0-9' <"$file")
            if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
                echo "$pid"
                return 0
            fi
        fi
        sleep 0.1
    done
    return 1
}

record() { echo "$1 $2" >>"$PIDS"; }

start_munge() {
    if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
        say "munged already running (not started here, left alone)"
        return
    fi
    if [ ! -s /etc/munge/munge.key ]; then
        say "creating /etc/munge/munge.key"
        install -d -o munge -g munge -m 700 /etc/munge
        dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    fi
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
    install -d -o munge -g munge -m 755 /run/munge
    install -d -o munge -g munge -m 700 /var/lib/munge /var/log/munge
    rm -f /run/munge/munged.pid
    runuser -u munge -- munged
    local pid
    pid=$(wait_pidfile /run/munge/munged.pid 10) || die "munged did not start (see /var/log/munge/munged.log)"
    record munged "$pid"
    say "munged started (PID $pid)"
}

write_conf() {
    if [ -f "$CONF" ] && ! grep -qF "$MARKER" "$CONF"; then
        say "using the existing $CONF (not written by this script)"
        return
    fi
    local host cpus mem
    host=$(hostname -s)
    cpus=$(nproc)
    mem=$(($(awk '/^MemTotal:/ {print int($2 / 1024)}' /proc/meminfo) - 1024))
    [ "$mem" -gt 512 ] || mem=512
    mkdir -p /etc/slurm
    cat >"$CONF" <<EOF
$MARKER
ClusterName=local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=$STATE_DIR/slurmctld.pid
SlurmdPidFile=$STATE_DIR/slurmd.pid
SlurmctldLogFile=$STATE_DIR/slurmctld.log
SlurmdLogFile=$STATE_DIR/slurmd.log
ReturnToService=2
MinJobAge=3600
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
    say "wrote $CONF (node $host, $cpus CPUs, $mem MiB)"
}

start_daemon() {
    local name=$1 pidfile=$STATE_DIR/$1.pid pid
    rm -f "$pidfile"
    "$name"
    pid=$(wait_pidfile "$pidfile" 20) || die "$name did not start (see $STATE_DIR/$name.log)"
    record "$name" "$pid"
    say "$name started (PID $pid)"
}

wait_idle() {
    local i state
    for ((i = 0; i < 60; i++)); do
        state=$(sinfo -h -o '%T' 2>/dev/null | head -n1 || true)
        case $state in
        idle* | mixed* | allocated*) say "node $state"; return 0 ;;
        down* | drain*) scontrol update nodename="$(hostname -s)" state=resume 2>/dev/null || true ;;
        esac
        sleep 1
    done
    die "the node did not become idle within 60 s (sinfo: ${state:-nothing}); see $STATE_DIR/*.log"
}

start() {
    need_root
    if [ -s "$PIDS" ]; then
        local alive=0 name pid
        while read -r name pid; do
            if kill -0 "$pid" 2>/dev/null; then alive=1; fi
        done <"$PIDS"
        if [ "$alive" = 1 ]; then
            say "already started (see: $0 status)"
            return 0
        fi
        rm -f "$PIDS"
    fi
    install_packages
    mkdir -p "$STATE_DIR" /var/spool/slurmctld /var/spool/slurmd
    : >"$PIDS"
    start_munge
    write_conf
    if scontrol ping 2>/dev/null | grep -q UP; then
        say "a slurmctld is already running (not started here; it and its slurmd are left alone)"
    else
        start_daemon slurmctld
        start_daemon slurmd
    fi
    wait_idle
    sinfo >&2
}

stop() {
    need_root
    if [ ! -s "$PIDS" ]; then
        say "nothing to stop (no daemons recorded in $PIDS)"
        return 0
    fi
    local name pid i
    # Reverse order: slurmd, slurmctld, then munged.
    tac "$PIDS" | while read -r name pid; do
        if kill -0 "$pid" 2>/dev/null; then
            kill -TERM "$pid" 2>/dev/null || true
            for ((i = 0; i < 100; i++)); do
                kill -0 "$pid" 2>/dev/null || break
                sleep 0.1
            done
            if kill -0 "$pid" 2>/dev/null; then
                kill -KILL "$pid" 2>/dev/null || true
                say "$name (PID $pid) killed"
            else
                say "$name (PID $pid) stopped"
            fi
        else
            say "$name (PID $pid) was not running"
        fi
    done
    rm -f "$PIDS"
}

status() {
    if [ -s "$PIDS" ]; then
        local name pid
        while read -r name pid; do
            if kill -0 "$pid" 2>/dev/null; then
                echo "$name PID $pid running"
            else
                echo "$name PID $pid not running"
            fi
        done <"$PIDS"
    else
        echo "no daemons started by this script"
    fi
    if command -v sinfo >/dev/null; then
        sinfo 2>&1 || true
    fi
}

case ${1:-} in
start) start ;;
stop) stop ;;
status) status ;;
*)
    echo "usage: $0 start|stop|status" >&2
    exit 2
    ;;
esac
