#!/bin/sh
# Processor-in-the-loop benchmark of the WHOLE control interrupt.
#
# 1. Records closed-loop SIL runs with the host build (dtc-sim run SCENARIO
#    --record-samples REC): every controller (ip, nominal, rbfn) over scenarios
#    that visit every run state and the worst cases: CASE2 (start, load step),
#    the nameplate and field-weakening runs (level changes, high speed, flux
#    reference below nominal), 30 rpm (low level, small vectors, NP balancing,
#    vector substitutions), a rated torque step at 500 rpm, a load driving the
#    motor at 300 rpm (regen_300rpm: the observer's regenerating-mode rotation),
#    the loss-of-control trip (runaway_trip with that rotation off, as
#    LossOfControl.SensorlessRunawayTrips forces it), CASE2 with an over-current
#    trip at 3 s (faulted) and
#    CASE2 with the run command 0.3 s late (stopped); and the first six
#    again as flashed (NAME_flashed: the firmware's default parameters, with
#    the real inverter's compensation, against a plant with the 1 V device
#    drop; the scenarios themselves set an ideal inverter), with the warm
#    stator run as flashed and its Rs adaptation on.
# 2. Replays all recordings in one run of dtc-pil.elf (Cortex-M4F, same
#    toolchain and flags as the target image) under qemu-system-arm mps2-an386
#    with exact instruction counting (-icount shift=7): the real interrupt path
#    (sample read -> ctl_step -> actuation -> telemetry snapshot -> scope armed)
#    fed with the recorded samples, its outputs compared bit for bit with the
#    host build's.
# Prints min / mean / max instructions per interrupt per controller and run
# state (the worst over everything run), the worst ticks, an estimate in
# cycles and microseconds at 170 MHz, and the interrupt's stack high-water.
#
# usage: tools/pil_bench.sh
# env:   DTC_PIL_NO_BUILD=1   use the existing builds (build/stm32g4, build/host)
#        DTC_PIL_REC_DIR      where to keep the recordings (default build/host/pil-rec)
#        DTC_PIL_CFLAGS       C flags added to the target's (all of dtc-pil's C code), for
#                             measuring a compiler option: dtc-pil.elf is then built afresh
#                             in build/stm32g4-cflags every time, even with DTC_PIL_NO_BUILD
#                             (the shipped build is not touched); the recordings still come
#                             from build/host (built unless DTC_PIL_NO_BUILD=1)
# exit:  dtc-pil's status (0 ok, 1 counter self-check failed, 2 bad recording or usage,
#        3 exception on the emulated core, 4 outputs differ from the host
#        build's), 124 on timeout, 127 missing tools, or dtc-sim's status.
set -eu

if [ $# -ne 0 ]; then
  echo "usage: tools/pil_bench.sh   (no arguments; env DTC_PIL_NO_BUILD, DTC_PIL_REC_DIR, DTC_PIL_CFLAGS)" >&2
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
elf=$root/build/stm32g4/dtc-pil.elf
sim=$root/build/host/bin/dtc-sim
rec=${DTC_PIL_REC_DIR:-$root/build/host/pil-rec}

missing=""
for tool in arm-none-eabi-gcc qemu-system-arm cmake ninja python3; do
  command -v "$tool" >/dev/null 2>&1 || missing="$missing $tool"
done
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "pil_bench.sh: installing missing tools:$missing" >&2
    apt-get update -qq
    apt-get install -y -qq gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm cmake ninja-build python3 >&2
  else
    echo "pil_bench.sh: missing:$missing (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm cmake ninja-build python3)" >&2
    exit 127
  fi
fi

if [ "${DTC_PIL_NO_BUILD:-0}" != 1 ]; then
  (cd "$root" && cmake --preset stm32g4 >/dev/null && cmake --build --preset stm32g4 --target dtc-pil) >&2
  (cd "$root" && cmake --preset host >/dev/null && cmake --build --preset host --target dtc-sim) >&2
fi
if [ -n "${DTC_PIL_CFLAGS:-}" ]; then
  # flags of a first configure only (CMAKE_C_FLAGS_INIT): a fresh directory every time
  cflags_build=$root/build/stm32g4-cflags
  rm -rf "$cflags_build"
  cmake -S "$root" -B "$cflags_build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$root/cmake/arm-none-eabi.cmake" \
    -DCMAKE_BUILD_TYPE=Release "-DDTC_EXTRA_C_FLAGS=$DTC_PIL_CFLAGS" >/dev/null
  cmake --build "$cflags_build" --target dtc-pil >&2
  elf=$cflags_build/dtc-pil.elf
  echo "dtc-pil.elf built with the target's C flags and: $DTC_PIL_CFLAGS"
fi
for f in "$elf" "$sim"; do
  if [ ! -x "$f" ] && [ ! -f "$f" ]; then
    echo "pil_bench.sh: $f not found (build the stm32g4 and host presets)" >&2
    exit 2
  fi
done

mkdir -p "$rec"
scn=$root/host_sim/scenarios
# NAME_flashed: the scenario as the image runs it when flashed (tools/scenario_as_flashed.py:
# the firmware's default parameters, so the real inverter's compensation on, against the plant's
# 1 V device drop), where the scenario itself sets an ideal inverter (v_drop_V = 0);
# warm_stator_flashed with the user's option that costs most per tick on: the stator-resistance
# adaptation (obs_ki_rs = 0.1, docs/envelope.md section 6: its terms worked out every tick)
flashed="case2_flashed nameplate_flashed field_weakening_flashed low_speed_30rpm_flashed rated_step_500_flashed runaway_trip_flashed warm_stator_flashed"
names="case2 nameplate field_weakening low_speed_30rpm rated_step_500 regen_300rpm runaway_trip case2_overcurrent case2_stopped $flashed"
for name in $flashed; do
  base=${name%_flashed}
  python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from scenario_as_flashed import as_flashed; as_flashed(sys.argv[2], sys.argv[3])' \
    "$root/tools" "$scn/$base.ini" "$rec/$name.ini"
done
# record NAME CONTROLLER: one closed-loop SIL run into $rec/NAME_CONTROLLER.rec
record() {
  out=$rec/$1_$2.rec
  case $1 in
    case2_overcurrent) set -- "$scn/case2.ini" --controller "$2" --set "faults.offset=3.0 a 120" ;;
    case2_stopped) set -- "$scn/case2.ini" --controller "$2" --start-delay 0.3 --duration 1.0 ;;
    runaway_trip) set -- "$scn/runaway_trip.ini" --controller "$2" --set control.obs_regen_angle_rad=0 ;;
    runaway_trip_flashed) set -- "$rec/$1.ini" --controller "$2" --set control.obs_regen_angle_rad=0 ;;
    warm_stator_flashed) set -- "$rec/$1.ini" --controller "$2" --set control.obs_ki_rs=0.1 ;;
    *_flashed) set -- "$rec/$1.ini" --controller "$2" ;;
    *) set -- "$scn/$1.ini" --controller "$2" ;;
  esac
  "$sim" run "$@" --quiet --record-samples "$out"
}

files=""
for ctl in ip nominal rbfn; do
  for name in $names; do
    record "$name" "$ctl"
    files="$files,arg=${name}_$ctl.rec" # relative to QEMU's directory (below): no path in the
    # semihosting command line, whose commas and spaces separate its arguments
  done
done

echo "recorded with $sim; replaying on $elf"
status=0
(cd "$rec" && timeout 1800 qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
  -semihosting-config "enable=on,target=native,arg=dtc-pil$files" \
  -icount shift=7 -kernel "$elf" 2>&1) || status=$?
if [ "$status" = 124 ]; then
  echo "pil_bench.sh: QEMU timed out" >&2
fi
exit "$status"
