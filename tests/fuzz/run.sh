#!/bin/sh
# Fuzz the harnesses of tests/fuzz with libFuzzer (clang) and the address and
# undefined-behaviour sanitizers, each for a time budget (docs/fuzzing.md).
#
#   tests/fuzz/run.sh [--seconds N] [--only NAME]
#       --seconds N   budget per harness, s (default 60)
#       --only NAME   canopen_drive or scenario_parser (default: both, in turn)
#
# Installs Debian's clang and libclang-rt-dev when libFuzzer is missing (as
# root). Builds into build/fuzz; each harness's corpus grows in
# build/fuzz/corpus/NAME (seeded from tests/fuzz/corpus/NAME, and for the
# parser the shipped scenarios); a finding is kept in build/fuzz/findings/NAME/
# and replays with `build/fuzz/bin/fuzz_NAME FILE` (or, without clang,
# build/host/bin/fuzz_NAME FILE).
# Prints per harness the executions, the time and the corpus size.
# exit: 0 no finding, 1 a finding, 2 usage or build failure.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
seconds=60
only=
while [ $# -gt 0 ]; do
  case $1 in
    --seconds) [ $# -ge 2 ] || { echo "run.sh: --seconds needs a value" >&2; exit 2; }
               seconds=$2; shift 2 ;;
    --only) [ $# -ge 2 ] || { echo "run.sh: --only needs a value" >&2; exit 2; }
            only=$2; shift 2 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case $seconds in ''|*[!0-9]*) echo "run.sh: --seconds '$seconds' is not a whole number of seconds" >&2; exit 2 ;; esac
case $only in ''|canopen_drive|scenario_parser) ;; *) echo "run.sh: --only '$only': canopen_drive or scenario_parser" >&2; exit 2 ;; esac

has_libfuzzer() {
  command -v clang++ >/dev/null 2>&1 || return 1
  t=$(mktemp -d)
  printf 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { return 0; }\n' >"$t/t.cpp"
  clang++ -fsanitize=fuzzer,address,undefined "$t/t.cpp" -o "$t/t" >/dev/null 2>&1
  rc=$?
  rm -rf "$t"
  return $rc
}
if ! has_libfuzzer; then
  echo "run.sh: installing clang and libclang-rt-dev (libFuzzer)" >&2
  if [ "$(id -u)" != 0 ]; then
    echo "run.sh: not root: install them yourself (apt-get install clang libclang-rt-dev)" >&2
    exit 2
  fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y clang libclang-rt-dev >/dev/null 2>&1 ||
    { apt-get update >/dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y clang libclang-rt-dev >/dev/null; } ||
    { echo "run.sh: apt-get install clang libclang-rt-dev failed" >&2; exit 2; }
  has_libfuzzer || { echo "run.sh: clang cannot link -fsanitize=fuzzer" >&2; exit 2; }
fi

build=$root/build/fuzz
# Coverage instrumentation everywhere (the harness links libFuzzer itself).
# clang has no -fsingle-precision-constant, which the host firmware build
# passes: unsuffixed constants are double here, so the warnings that follow
# from that (promotions, the ignored flag) are not errors in this build.
cflags="-fsanitize=fuzzer-no-link -Wno-ignored-optimization-argument -Wno-double-promotion"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DDTC_SANITIZE=ON -DDTC_FUZZ_LIBFUZZER=ON \
  -DCMAKE_C_FLAGS="$cflags" -DCMAKE_CXX_FLAGS="$cflags" >"$build.configure.log" 2>&1 ||
  { echo "run.sh: configure failed, see $build.configure.log" >&2; exit 2; }
cmake --build "$build" --target fuzz_canopen_drive fuzz_scenario_parser >"$build.build.log" 2>&1 ||
  { echo "run.sh: build failed, see $build.build.log" >&2; exit 2; }

status=0
for name in canopen_drive scenario_parser; do
  [ -z "$only" ] || [ "$only" = "$name" ] || continue
  corpus=$build/corpus/$name
  findings=$build/findings/$name
  mkdir -p "$corpus" "$findings"
  seeds=$root/tests/fuzz/corpus/$name
  extra=
  [ "$name" = scenario_parser ] && extra=$root/host_sim/scenarios
  log=$build/$name.log
  # -rss_limit_mb: the drive struct and the board are a few hundred kB; a
  # growth past this is a leak. -timeout: one input runs in milliseconds.
  if "$build/bin/fuzz_$name" -max_total_time="$seconds" -print_final_stats=1 -timeout=10 \
       -rss_limit_mb=2048 -artifact_prefix="$findings/" "$corpus" "$seeds" $extra >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    n=$(find "$corpus" -type f | wc -l)
    echo "fuzz_$name: ${execs:-?} executions in $seconds s, corpus $n inputs, no finding"
  else
    echo "fuzz_$name: FINDING, see $log and $findings/" >&2
    grep -E "invariant violated|ERROR: |SUMMARY: " "$log" | head -n 5 >&2 || true
    status=1
  fi
done
exit $status
