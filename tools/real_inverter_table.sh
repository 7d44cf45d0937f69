#!/bin/sh
# The envelope's scenarios on the plant's default (real) inverter: 2 us dead
# time without compensation in the power stage, 1 V per device; the firmware
# compensates both in its voltage model (v_drop_V, dead_time_comp_s, which
# dtc-sim commissions from the plant's dead time). Prints the markdown table
# of docs/envelope.md, "On the real inverter".
#   usage: tools/real_inverter_table.sh        (build the host preset first)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
sim=${DTC_SIM:-$root/build/host/bin/dtc-sim}
[ -x "$sim" ] || { echo "real_inverter_table.sh: $sim not found: cmake --preset host && cmake --build --preset host" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| scenario | controller | steady error | recovery | NP max | f_sw | faults | final speed |"
echo "|---|---|---|---|---|---|---|---|"
for f in rated_step_500 nameplate field_weakening low_speed_30rpm low_speed_10rpm regen_300rpm; do
  for c in rbfn ip; do
    "$sim" run "$root/host_sim/scenarios/$f.ini" --controller "$c" --quiet \
      --set inverter.dead_time_s=2e-6 --set inverter.v_on_V=1 --set control.v_drop_V=1 \
      --metrics "$tmp/$f-$c.json"
    python3 - "$tmp/$f-$c.json" "$f" "$c" <<'P'
import json, sys
m = json.load(open(sys.argv[1]))
f, c = sys.argv[2], sys.argv[3]
rec = "%.3f s" % m["recovery_time_s"] if f in ("rated_step_500", "nameplate", "field_weakening") else "-"
print("| %s | %s | %.2f rpm | %s | %.2f V | %.0f Hz | 0x%x | %.1f rpm |"
      % (f, c, m["steady_error_rpm"], rec, m["np_dev_max_v"], m["switching_freq_hz"], m["faults"], m["speed_true_end_rpm"]))
P
  done
done
