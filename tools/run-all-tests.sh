#!/usr/bin/env bash
# The project's test command: install what is missing, build the host SIL and
# the Cortex-M4F firmware, and run every test (unit, SIL, CAN over real
# SocketCAN in User-Mode Linux, tool tests). Safe to run again.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"

tools/install-deps.sh

# The target first: the emulated board's tests link test images against the target build's
# firmware libraries, which the host configure looks for.
echo "== Cortex-M4F firmware build"
cmake --preset stm32g4 >/dev/null
cmake --build --preset stm32g4

echo "== host build"
cmake --preset host >/dev/null
cmake --build --preset host

echo "== tests"
ctest --preset host
