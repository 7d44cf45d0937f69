#!/usr/bin/env bash
# Issue 8 part 3, the proof: sweep the drive's torque-speed plane with the firmware
# defaults (RBFN), both directions, motoring and generating, 0 to 1.5 x base speed,
# 0 to the rated torque limit (108 points per inverter model), every point a dtc-sim
# run in a process pool of one worker per core; print the table and write the
# capability map. Safe to run again. Design and results: docs/envelope.md,
# "Capability sweep".
# Output: out/envelope/capability.png (copied to docs/envelope-map.png),
#         out/envelope/{real,ideal}/results.{csv,json},
#         out/envelope/{real,ideal}/points/*.ini (re-run one: dtc-sim run FILE) and *.json
# Arguments are passed to tools/envelope_sweep.py (e.g. --inverter real, --jobs 1).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"

tools/install-deps.sh
cmake --preset host >/dev/null
cmake --build --preset host >/dev/null

.venv/bin/python tools/envelope_sweep.py --inverter both --docs-png docs/envelope-map.png "$@"
