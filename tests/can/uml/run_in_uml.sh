#!/usr/bin/env bash
# Run a command where real SocketCAN with a vcan0 interface exists.
#
#   tests/can/uml/run_in_uml.sh [--timeout SECONDS] [--uml|--direct] [--] COMMAND [ARGS...]
#
# If the host kernel has vcan (vcan0 is up already, or `ip link add vcan0 type vcan`
# works), COMMAND runs directly on the host. Otherwise (this machine's kernel has no
# CAN at all) it boots User-Mode Linux, whose modules carry CAN and vcan, with the
# host's file system as the guest's root, and runs COMMAND in there as root.
# COMMAND runs in the current directory with PATH (the repo's .venv/bin first when it
# exists), HOME, LANG, PYTHONPATH, MPLBACKEND and every DTC_* variable of the caller;
# nothing else crosses into the guest. Its output appears on our stdout.
#
# Exit status: COMMAND's; 124 when it ran out of time; 125 when the guest could not
# set up CAN; 126 when User-Mode Linux is missing or the guest did not report.
# --timeout bounds the command (default 300 s); the whole run is bounded by it plus 60 s.
# --uml forces User-Mode Linux even where the host has vcan; --direct forbids it.
set -uo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../../.." && pwd)
limit=300
mode=auto
while (($#)); do
    case "$1" in
        --timeout) limit=${2:?--timeout needs seconds}; shift 2 ;;
        --timeout=*) limit=${1#--timeout=}; shift ;;
        --uml) mode=uml; shift ;;
        --direct) mode=direct; shift ;;
        --) shift; break ;;
        -h|--help) sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "run_in_uml: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
if (($# == 0)); then
    echo "run_in_uml: no command given (usage: run_in_uml.sh [--timeout S] [--] COMMAND [ARGS...])" >&2
    exit 2
fi
case "$limit" in ''|*[!0-9]*) echo "run_in_uml: --timeout must be whole seconds, got '$limit'" >&2; exit 2 ;; esac

path=$PATH
[ -x "$repo/.venv/bin/python" ] && path="$repo/.venv/bin:$path"

host_has_vcan() {
    # vcan0 already up, or we may create it (root on a kernel with the vcan module).
    if ip link show vcan0 2>/dev/null | grep -q 'state \(UP\|UNKNOWN\)'; then
        return 0
    fi
    [ "$(id -u)" -eq 0 ] || return 1
    modprobe vcan 2>/dev/null
    if ip link show vcan0 >/dev/null 2>&1 || ip link add dev vcan0 type vcan 2>/dev/null; then
        ip link set up vcan0 2>/dev/null && return 0
    fi
    return 1
}

if [ "$mode" != uml ] && host_has_vcan; then
    echo "run_in_uml: the host kernel has vcan0; running directly"
    PATH=$path exec timeout -k 10 "$limit" "$@"
fi
if [ "$mode" = direct ]; then
    echo "run_in_uml: --direct, but the host kernel has no vcan" >&2
    exit 126
fi

# tools/install-uml.sh puts a newer kernel with its modules in .uml/ where Debian 12's cannot
# run a process on the host (AMX hosts under recent kernels).
if [ -x "$repo/.uml/bin/linux.uml" ]; then
    uml=$repo/.uml/bin/linux.uml
    modules=$repo/.uml/modules
else
    uml=$(command -v linux.uml || command -v linux || true)
    modules=/usr/lib/uml/modules
fi
if [ -z "$uml" ] || [ ! -d "$modules" ]; then
    echo "run_in_uml: User-Mode Linux is not installed (tools/install-deps.sh installs it)" >&2
    exit 126
fi

# The job directory is on the host file system, which is the guest's root.
job=$(mktemp -d "${TMPDIR:-/tmp}/dtc-uml.XXXXXX") || exit 126
trap 'rm -rf "$job"' EXIT
{
    echo "# written by run_in_uml.sh"
    printf 'cd %q || exit 125\n' "$PWD"
    printf 'export PATH=%q\n' "$path"
    printf 'export HOME=%q\n' "${HOME:-/root}"
    for v in LANG PYTHONPATH MPLBACKEND VIRTUAL_ENV $(compgen -v DTC_); do
        [ -n "${!v+x}" ] && printf 'export %s=%q\n' "$v" "${!v}"
    done
    printf 'exec'
    printf ' %q' "$@"
    printf '\n'
} > "$job/cmd.sh"

echo "run_in_uml: booting User-Mode Linux ($uml) for: $*"
# con0 on our stdin/stdout carries the command's output; `quiet` keeps kernel chatter out.
# Unknown key=value boot parameters become the environment of init (guest_init.sh).
timeout -k 10 $((limit + 60)) "$uml" mem=512M rootfstype=hostfs rw quiet loglevel=1 \
    init="$here/guest_init.sh" dtc_job="$job" dtc_timeout="$limit" dtc_modules="$modules" \
    con=null con0=fd:0,fd:1 </dev/null | sed -u 's/\r//g'
uml_status=${PIPESTATUS[0]}

if [ ! -s "$job/rc" ]; then
    if [ "$uml_status" -eq 124 ]; then
        echo "run_in_uml: User-Mode Linux did not halt within $((limit + 60)) s; killed" >&2
    else
        echo "run_in_uml: the guest did not report an exit code (User-Mode Linux exit status $uml_status)" >&2
    fi
    exit 126
fi
rc=$(cat "$job/rc")
[ "$rc" -eq 124 ] && echo "run_in_uml: the command ran out of time (--timeout $limit s)" >&2
exit "$rc"
