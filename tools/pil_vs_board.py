#!/usr/bin/env python3
"""The PIL bench against the emulated board: instructions of the control interrupt.

For each controller, CASE2 as the twin runs it (tests/board/test_twin.py: no [control] section,
the plant's device drop v_on_V = 1 V, which the firmware's default v_drop_V compensates):
  * the twin: `dtc-board run CASE2 --elf build/stm32g4/dtc-fw.elf --controller C --metrics M`,
    field board.interrupt_instructions["ADC1_2 (control tick)"] (best / mean / worst): the
    flashable image's whole ADC1_2_IRQHandler on its own closed loop (twin plant, ADC codes);
  * the PIL: `dtc-sim run CASE2 --controller C --record-samples R`, then dtc-pil.elf replays R
    under QEMU (min / mean / max of its tick interrupt, hal/pil/pil_bench.c).
Prints both and the differences. docs/pil.md explains them.

usage: tools/pil_vs_board.py            (builds nothing: build both presets first)
"""
import json
import os
import re
import subprocess
import sys
import tempfile

from scenario_as_flashed import as_flashed

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(SRC, "build", "host", "bin")
FW = os.path.join(SRC, "build", "stm32g4", "dtc-fw.elf")
PIL = os.path.join(SRC, "build", "stm32g4", "dtc-pil.elf")
CASE2 = os.path.join(SRC, "host_sim", "scenarios", "case2.ini")
TICK = "ADC1_2 (control tick)"


def case2_as_flashed(tmp):
    return as_flashed(CASE2, os.path.join(tmp, "case2_as_flashed.ini"))


def run(args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(args)}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    return r.stdout + r.stderr


def main():
    for f in (FW, PIL, os.path.join(BIN, "dtc-sim"), os.path.join(BIN, "dtc-board")):
        if not os.path.isfile(f):
            sys.exit(f"pil_vs_board: {f} missing (build the stm32g4 and host presets)")
    ctls = ("ip", "nominal", "rbfn")
    twin, recs = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        scn = case2_as_flashed(tmp)
        for c in ctls:
            m = os.path.join(tmp, f"board_{c}.json")
            run([os.path.join(BIN, "dtc-board"), "run", scn, "--elf", FW, "--controller", c, "--metrics", m, "--quiet"])
            with open(m) as f:
                twin[c] = json.load(f)["board"]["interrupt_instructions"][TICK]
            r = os.path.join(tmp, f"case2_as_flashed_{c}.rec")
            run([os.path.join(BIN, "dtc-sim"), "run", scn, "--controller", c, "--quiet", "--record-samples", r])
            recs.append(r)
        out = run(["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
                   "-semihosting-config", "enable=on,target=native,arg=dtc-pil," + ",".join("arg=" + r for r in recs),
                   "-icount", "shift=7", "-kernel", PIL])
    pil = {}
    for m in re.finditer(r"\((\w+)\): (\d+) ticks, min (\d+), mean ([\d.]+), max (\d+)", out):
        pil[m.group(1)] = (int(m.group(2)), int(m.group(3)), float(m.group(4)), int(m.group(5)))
    print("CASE2 as flashed, instructions of the control interrupt per tick")
    print("| controller | twin ticks | twin best / mean / worst | PIL ticks | PIL min / mean / max | mean: twin - PIL | worst: twin - PIL |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for c in ctls:
        t, p = twin[c], pil[c]
        print(f"| {c} | {t['count']} | {t['best']} / {t['mean']:.1f} / {t['worst']} | {p[0]} | {p[1]} / {p[2]:.1f} / {p[3]} "
              f"| {t['mean'] - p[2]:+.1f} ({(t['mean'] - p[2]) / p[2] * 100:+.1f} %) "
              f"| {t['worst'] - p[3]:+d} ({(t['worst'] - p[3]) / p[3] * 100:+.1f} %) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
