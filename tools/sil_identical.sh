#!/bin/sh
# Proves that a change of the firmware leaves every numerical result of the SIL
# runs bit for bit as it was (for refactoring and cycle-count work: the SIL
# metrics are chaotic, so a one-ulp change would move them).
#
#   tools/sil_identical.sh record OUT_DIR [DTC_SIM]
#       runs every scenario of host_sim/scenarios with every controller
#       (ip, nominal, rbfn) and keeps, per run, the trace (.csv), the metrics
#       (.json) and the per-tick interrupt inputs and outputs (.rec, every tick:
#       torque reference, chosen vectors, duty split, observer state).
#       DTC_SIM defaults to build/host/bin/dtc-sim.
#   tools/sil_identical.sh compare BEFORE_DIR AFTER_DIR
#       requires byte-identical .csv and .rec files (a .rec past its header's scenario name) and identical metrics
#       except the host's wall-clock fields (tools/compare_metrics.py).
#
# Typical use: record build A into DIR_A, change the code, rebuild, record
# into DIR_B, compare DIR_A DIR_B.
# exit: 0 identical, 1 something differs, 2 usage or a run failed.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  echo "usage: tools/sil_identical.sh record OUT_DIR [DTC_SIM] | compare BEFORE_DIR AFTER_DIR" >&2
  exit 2
}

[ $# -ge 2 ] || usage
case $1 in
  record)
    [ $# -le 3 ] || usage
    out=$2
    sim=${3:-$root/build/host/bin/dtc-sim}
    [ -x "$sim" ] || { echo "sil_identical.sh: $sim not found" >&2; exit 2; }
    mkdir -p "$out"
    n=0
    for scen in "$root"/host_sim/scenarios/*.ini; do
      base=$(basename "$scen" .ini)
      for ctl in ip nominal rbfn; do
        o=$out/${base}_$ctl
        # open-loop scenarios (no firmware) have no interrupt to record
        if ! "$sim" run "$scen" --controller "$ctl" --quiet --csv "$o.csv" --metrics "$o.json" \
          --record-samples "$o.rec" 2>/dev/null; then
          "$sim" run "$scen" --controller "$ctl" --quiet --csv "$o.csv" --metrics "$o.json" ||
            { echo "sil_identical.sh: $base ($ctl) failed" >&2; exit 2; }
          echo "$base ($ctl): no recording (open loop)"
        fi
        n=$((n + 1))
      done
    done
    echo "recorded $n runs into $out"
    ;;
  compare)
    [ $# -eq 3 ] || usage
    a=$2
    b=$3
    differ=0
    count=0
    for f in "$a"/*.csv "$a"/*.rec; do
      [ -f "$f" ] || continue
      count=$((count + 1))
      g=$b/$(basename "$f")
      # a recording's header keeps the scenario's name (bytes 36..95: the path it was
      # run from, which differs between checkouts); every other byte must match
      case $f in
        *.rec) same() { cmp -s -n 36 "$1" "$2" && cmp -s -i 96 "$1" "$2"; } ;;
        *) same() { cmp -s "$1" "$2"; } ;;
      esac
      if ! same "$f" "$g"; then
        echo "DIFFERENT: $(basename "$f")"
        differ=1
      fi
    done
    [ "$count" -gt 0 ] || { echo "sil_identical.sh: no .csv/.rec in $a" >&2; exit 2; }
    py=$root/.venv/bin/python
    [ -x "$py" ] || py=python3
    if ! "$py" "$root/tools/compare_metrics.py" "$a" "$b" >"$b/compare_metrics.txt" 2>&1; then
      grep -v identical "$b/compare_metrics.txt" || true
      differ=1
    fi
    if [ "$differ" = 0 ]; then
      echo "identical: $count trace/recording files byte for byte, metrics field for field (wall clock aside)"
    fi
    exit "$differ"
    ;;
  *) usage ;;
esac
