#!/bin/sh
# PID 1 of the User-Mode Linux guest started by run_in_uml.sh.
#
# The guest's root file system is the host's (hostfs), so the project's
# binaries and the venv run as they are. The kernel passes the unknown
# boot parameters dtc_job=DIR, dtc_timeout=SECONDS and dtc_modules=DIR to us as environment
# variables; DIR holds `cmd.sh` (the command, its working directory and
# environment, written by the host side) and receives `rc` (the exit code).
# Nothing else is inherited from the host environment.
PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
export PATH

job=${dtc_job:-}
limit=${dtc_timeout:-300}

finish() {
    # $1: exit code reported to the host. sync first: halt -f does not flush.
    if [ -n "$job" ] && [ -d "$job" ]; then
        echo "$1" > "$job/rc"
    fi
    sync
    halt -f
    poweroff -f
    exit "$1"
}

fail() {
    echo "guest_init: $*" >&2
    finish 125
}

[ -n "$job" ] && [ -r "$job/cmd.sh" ] || fail "no job: dtc_job=$job has no cmd.sh"

mount -t proc proc /proc || fail "cannot mount /proc"
mount -t sysfs sys /sys || fail "cannot mount /sys"
# /tmp is the host's /tmp (hostfs); /dev/shm (POSIX semaphores, shared memory) is the guest's own.
mkdir -p /dev/shm && mount -t tmpfs -o size=64m tmpfs /dev/shm 2>/dev/null
ip link set lo up 2>/dev/null

modules=${dtc_modules:-/usr/lib/uml/modules}/$(uname -r)/kernel
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko; do
    insmod "$modules/$m" || fail "insmod $modules/$m failed (is the user-mode-linux package installed?)"
done
ip link add dev vcan0 type vcan || fail "cannot create vcan0"
# A deep transmit queue, like a real CAN controller's FIFO plus driver queue.
ip link set vcan0 txqueuelen 1000 2>/dev/null
ip link set up vcan0 || fail "cannot bring vcan0 up"

# The command's own time limit leaves the host side time to collect the result.
timeout -k 5 "$limit" /bin/sh "$job/cmd.sh"
finish $?
