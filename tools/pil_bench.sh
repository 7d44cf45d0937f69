#!/bin/sh
# Processor-in-the-loop benchmark: build dtc-pil.elf with the Cortex-M4F
# toolchain (preset stm32g4) and run it under qemu-system-arm (mps2-an386)
# with exact instruction counting (-icount shift=7). Prints instructions per
# control tick (min / mean / max) for each speed controller.
#
# usage: tools/pil_bench.sh [ticks]        ticks: control ticks per controller
#                                           (1..1000000, default 5000 = 1 s)
# env:   DTC_PIL_BUILD  build directory (default build/stm32g4)
#        DTC_PIL_NO_BUILD=1  run the existing ELF without rebuilding
# exit:  the program's status (0 ok, 1 counter self-check failed, 2 usage,
#        3 exception on the emulated core), 124 on timeout, 127 missing tools.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${DTC_PIL_BUILD:-$root/build/stm32g4}
ticks=${1:-5000}

case $ticks in
  ''|*[!0-9]*) echo "pil_bench.sh: ticks must be a positive integer, got '$ticks'" >&2; exit 2 ;;
esac

# A fresh machine has none of the tools: install them when we can (Debian).
missing=""
for tool in arm-none-eabi-gcc qemu-system-arm cmake ninja; do
  command -v "$tool" >/dev/null 2>&1 || missing="$missing $tool"
done
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "pil_bench.sh: installing missing tools:$missing" >&2
    apt-get update -qq
    apt-get install -y -qq gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm cmake ninja-build >&2
  else
    echo "pil_bench.sh: missing:$missing (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm cmake ninja-build)" >&2
    exit 127
  fi
fi

if [ "${DTC_PIL_NO_BUILD:-0}" != 1 ]; then
  if [ "$build" = "$root/build/stm32g4" ]; then
    (cd "$root" && cmake --preset stm32g4 >/dev/null && cmake --build --preset stm32g4 --target dtc-pil) >&2
  else
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_TOOLCHAIN_FILE="$root/cmake/arm-none-eabi.cmake" >/dev/null
    cmake --build "$build" --target dtc-pil >&2
  fi
fi

elf=$build/dtc-pil.elf
if [ ! -f "$elf" ]; then
  echo "pil_bench.sh: $elf not found" >&2
  exit 2
fi

# Semihosting output arrives on QEMU's stderr; pass it to our stdout.
# The emulated program's exit status becomes QEMU's (SYS_EXIT_EXTENDED).
status=0
timeout 900 qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native,arg=dtc-pil,arg="$ticks" \
  -icount shift=7 -kernel "$elf" 2>&1 || status=$?
if [ "$status" = 124 ]; then
  echo "pil_bench.sh: QEMU timed out" >&2
fi
exit "$status"
