#!/usr/bin/env python3
"""Instructions per control interrupt of the real image on the emulated board, per scenario
and controller: the whole ADC1_2 interrupt (sample read -> ctl_step -> actuation -> snapshot
and scope), counted exactly by dtc-board (best / mean / worst over every tick of the run).

usage: tools/twin_tick_table.py [--build-host DIR] [--elf FILE] [SCENARIO ...]
       [--controllers rbfn,ip,nominal]

SCENARIO is a name in host_sim/scenarios (default: case2 nameplate field_weakening
low_speed_30rpm rated_step_500). Each is run as flashed, as tests/board/test_twin.py does: the
[control] section is dropped (the twin commands the image through its RAM, not the CAN parameter
path) and the plant's device drop is the firmware's default 1 V. Build both presets first
(cmake --preset stm32g4 && cmake --build --preset stm32g4, then the host preset).
Exit status: 0 done, 1 a run failed, 2 usage.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from scenario_as_flashed import as_flashed

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENARIOS = ["case2", "nameplate", "field_weakening", "low_speed_30rpm", "rated_step_500"]
TICK = "ADC1_2 (control tick)"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="*", default=DEFAULT_SCENARIOS)
    ap.add_argument("--build-host", default=os.path.join(ROOT, "build", "host"))
    ap.add_argument("--elf", default=os.path.join(ROOT, "build", "stm32g4", "dtc-fw.elf"))
    ap.add_argument("--controllers", default="rbfn,ip,nominal")
    a = ap.parse_args()
    board = os.path.join(a.build_host, "bin", "dtc-board")
    for path in (board, a.elf):
        if not os.path.exists(path):
            print(f"twin_tick_table.py: {path} not found (build both presets first)", file=sys.stderr)
            return 2
    failed = 0
    print(f"{'scenario':18s} {'controller':10s} {'ticks':>6s} {'best':>6s} {'mean':>8s} {'worst':>6s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenarios:
            src = os.path.join(ROOT, "host_sim", "scenarios", name + ".ini")
            if not os.path.exists(src):
                print(f"twin_tick_table.py: no scenario {src}", file=sys.stderr)
                return 2
            ini = os.path.join(tmp, name + ".ini")
            as_flashed(src, ini)
            for ctl in a.controllers.split(","):
                m = os.path.join(tmp, f"{name}_{ctl}.json")
                r = subprocess.run([board, "run", ini, "--elf", a.elf, "--controller", ctl, "--metrics", m,
                                    "--quiet"], capture_output=True, text=True)
                if r.returncode != 0:
                    print(f"{name:18s} {ctl:10s} failed: {r.stderr.strip()[:200]}")
                    failed = 1
                    continue
                with open(m) as f:
                    j = json.load(f)
                t = j["board"]["interrupt_instructions"][TICK]
                faults = j.get("faults", 0)
                note = f"  faults {faults:#x}" if faults else ""
                print(f"{name:18s} {ctl:10s} {t['count']:6d} {t['best']:6d} {t['mean']:8.1f} {t['worst']:6d}{note}",
                      flush=True)
    return failed


if __name__ == "__main__":
    sys.exit(main())
