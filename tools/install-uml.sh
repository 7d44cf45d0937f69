#!/usr/bin/env bash
# Make sure a User-Mode Linux kernel boots on this host; the CAN tests need one.
#
# Debian 12's user-mode-linux (6.1) and Debian 13's (6.12) cannot start a single process on a
# host whose CPU has AMX tile state under a recent host kernel: the guest's first process dies at
# once ("ptrace set fp regs failed, errno = 14", init killed by SIGSEGV), because their buffer for
# a process's extended FPU state is smaller than the host's. Newer UML kernels size it from the
# host. So: boot the installed kernel once with a two-line init; if that fails, take
# user-mode-linux from Debian unstable (its kernel and CAN modules) into .uml/ of the checkout,
# with a C library of the same suite as its loader (it needs glibc 2.38; Debian 12 has 2.36).
# tests/can/uml/run_in_uml.sh uses .uml/bin/linux.uml when it exists. Safe to run again.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dest=$repo/.uml
mirror=${DTC_DEBIAN_MIRROR:-http://deb.debian.org/debian}

# boots KERNEL: 0 when a process ran inside it and it halted
boots() {
    local kernel=$1 work
    work=$(mktemp -d "${TMPDIR:-/tmp}/dtc-uml-probe.XXXXXX")
    printf '#!/bin/sh\necho dtc-uml-probe-ran\nhalt -f\n' > "$work/init"
    chmod +x "$work/init"
    local out
    out=$(timeout -k 5 60 "$kernel" mem=128M rootfstype=hostfs rw init="$work/init" \
          con=null con0=fd:0,fd:1 </dev/null 2>&1 || true)
    rm -rf "$work"
    grep -q dtc-uml-probe-ran <<<"$out"
}

if [ -x "$dest/bin/linux.uml" ] && boots "$dest/bin/linux.uml"; then
    exit 0
fi
system=$(command -v linux.uml || true)
if [ -n "$system" ] && boots "$system"; then
    rm -rf "$dest"
    exit 0
fi

echo "install-uml: ${system:-linux.uml} cannot run a process on this host; fetching user-mode-linux from Debian unstable into .uml/"
command -v patchelf >/dev/null || { echo "install-uml: patchelf is missing (apt-get install patchelf)" >&2; exit 1; }
work=$(mktemp -d "${TMPDIR:-/tmp}/dtc-uml-fetch.XXXXXX")
trap 'rm -rf "$work"' EXIT
curl -fsS -m 300 -o "$work/Packages.xz" "$mirror/dists/unstable/main/binary-amd64/Packages.xz"
xz -d "$work/Packages.xz"
# filename PACKAGE: the pool path of PACKAGE in that index
filename() {
    awk -v pkg="$1" '$0 == "Package: " pkg {p = 1} p && /^Filename:/ {print $2; exit}' "$work/Packages"
}
stage=$work/root
mkdir -p "$stage"
for pkg in user-mode-linux libc6; do
    f=$(filename "$pkg")
    [ -n "$f" ] || { echo "install-uml: $pkg not found in $mirror unstable" >&2; exit 1; }
    curl -fsS -m 600 -o "$work/$pkg.deb" "$mirror/$f"
    dpkg-deb -x "$work/$pkg.deb" "$stage"
    echo "install-uml: $(basename "$f")"
done
rm -rf "$dest.new"
mkdir -p "$dest.new/bin"
mv "$stage/usr/lib/uml/modules" "$dest.new/modules"
mv "$stage/usr/lib/x86_64-linux-gnu" "$dest.new/lib"
cp "$stage/usr/bin/linux.uml" "$dest.new/bin/linux.uml"
patchelf --set-interpreter "$dest/lib/ld-linux-x86-64.so.2" --set-rpath "$dest/lib" "$dest.new/bin/linux.uml"
rm -rf "$dest"
mv "$dest.new" "$dest"
if ! boots "$dest/bin/linux.uml"; then
    echo "install-uml: Debian unstable's user-mode-linux does not run a process on this host either" >&2
    exit 1
fi
echo "install-uml: .uml/bin/linux.uml ($(ls "$dest/modules")) boots"
