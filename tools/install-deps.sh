#!/usr/bin/env bash
# Install what the project needs on a fresh Debian 12 machine, then stop.
# Safe to run again: it installs only what is missing and reuses the venv.
#   Debian packages: compilers and libraries for the host SIL and the target,
#   QEMU (PIL), User-Mode Linux and can-utils (real SocketCAN in the tests; a newer UML kernel
#   in .uml/ where Debian 12's cannot run on the host, tools/install-uml.sh),
#   Unicorn (the emulated board, dtc-board), OpenOCD (flashing).
#   Python venv at .venv with dtctune and its pinned PyPI dependencies (tools/setup_venv.sh).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

packages=(build-essential cmake ninja-build pkg-config python3 python3-venv python3-pip
          googletest libgtest-dev libeigen3-dev libinih-dev libcjson-dev
          gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi qemu-system-arm
          user-mode-linux kmod can-utils iproute2 libunicorn-dev openocd
          curl xz-utils patchelf)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

"$repo/tools/install-uml.sh"
"$repo/tools/setup_venv.sh" >/dev/null
