#!/usr/bin/env bash
# The main job: build the host SIL and run the paper's CASE2 (500 rpm; at 2.5 s
# J and B x1.4 and an 8 N m load) with the IP and the RBFN speed controllers,
# print a table of the metrics and write the figures. Safe to run again.
# Output: out/paper/{ip,rbfn}.csv, {ip,rbfn}.json, case2.png
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"

tools/install-deps.sh
cmake --preset host >/dev/null
cmake --build --preset host >/dev/null

out="$repo/out/paper"
mkdir -p "$out"
for c in ip nominal rbfn; do
  build/host/bin/dtc-sim run host_sim/scenarios/case2.ini --controller "$c" \
    --csv "$out/$c.csv" --metrics "$out/$c.json" >/dev/null
done
.venv/bin/python tools/metrics_table.py "$out"/ip.json "$out"/nominal.json "$out"/rbfn.json
.venv/bin/python tools/plot_traces.py --ip "$out/ip.csv" --rbfn "$out/rbfn.csv" --out "$out/case2.png"
echo "figures: $out/case2.png"
