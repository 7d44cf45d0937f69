#!/usr/bin/env python3
"""PIL equivalence: the same recorded CASE2 input sequence through the host build and the
Cortex-M4F build.

  test_pil_equiv.py CONTROLLER         dtc-sim (host build) runs CASE2 closed loop with
                                       CONTROLLER and records every tick's interrupt inputs and
                                       outputs (--record-samples); dtc-pil.elf (the Cortex-M4F
                                       build of the same firmware, QEMU mps2-an386) replays the
                                       inputs through drive_isr and must produce bit-identical
                                       outputs (vectors, duty split, run state, faults, torque
                                       reference, flux, speed estimate, observer state) at every
                                       one of the >= 5,000 ticks; else it names the first
                                       differing tick and field.
  test_pil_equiv.py tamper             the comparison can fail: one bit of the recorded torque
                                       reference flipped at tick 2000 must be reported as the
                                       first difference, at that tick and field (exit 4).
Exit 77 (skipped) when dtc-pil.elf has not been built (cmake --preset stm32g4) or QEMU is missing.
"""
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("DTC_HOST_BIN", os.path.join(SRC, "build", "host", "bin"))
ELF = os.environ.get("DTC_PIL_ELF", os.path.join(SRC, "build", "stm32g4", "dtc-pil.elf"))
CASE2 = os.path.join(SRC, "host_sim", "scenarios", "case2.ini")
MIN_TICKS = 5000
HEADER_BYTES, RECORD_BYTES = 96, 124  # recording/include/recording/tick_record.h
TE_REF_OFFSET = 64                    # byte offset of te_ref_Nm in a record (tick_record.c)


def run_pil(rec):
    r = subprocess.run(["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none",
                        "-serial", "none", "-semihosting-config",
                        f"enable=on,target=native,arg=dtc-pil,arg={rec}",
                        "-icount", "shift=7", "-kernel", ELF],
                       capture_output=True, text=True, timeout=600)
    out = r.stdout + r.stderr
    print(out.strip())
    return r.returncode, out


def record(tmp, ctl):
    rec = os.path.join(tmp, f"case2_{ctl}.rec")
    r = subprocess.run([os.path.join(BIN, "dtc-sim"), "run", CASE2, "--controller", ctl, "--quiet",
                        "--record-samples", rec], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"dtc-sim failed: {r.stdout}{r.stderr}")
    return rec


def main():
    if len(sys.argv) != 2 or sys.argv[1] not in ("ip", "nominal", "rbfn", "tamper"):
        sys.exit(__doc__)
    if not os.path.isfile(ELF) or shutil.which("qemu-system-arm") is None:
        print(f"skipped: {ELF} or qemu-system-arm missing")
        return 77
    with tempfile.TemporaryDirectory() as tmp:
        if sys.argv[1] == "tamper":
            rec = record(tmp, "rbfn")
            with open(rec, "r+b") as f:
                cfg_words = struct.unpack_from("<I", f.read(HEADER_BYTES), 20)[0]
                at = HEADER_BYTES + 4 * cfg_words + 2000 * RECORD_BYTES + TE_REF_OFFSET
                f.seek(at)
                b = f.read(1)
                f.seek(at)
                f.write(bytes([b[0] ^ 1]))  # the least significant mantissa bit
            rc, out = run_pil(rec)
            ok = rc == 4 and "first difference at tick 2000: tel.te_ref_Nm" in out
            print(("ok   " if ok else "FAIL ") + "a one-ulp change of the recorded torque reference at tick 2000 "
                  "is found at that tick and field (exit 4)")
            return 0 if ok else 1
        rec = record(tmp, sys.argv[1])
        rc, out = run_pil(rec)
        m = re.search(r"\((\w+)\): (\d+) ticks, .*; bit-identical to the host build", out)
        failures = []
        if rc != 0:
            failures.append(f"dtc-pil exit status {rc} (4: outputs differ)")
        if not m or m.group(1) != sys.argv[1]:
            failures.append(f"no bit-identical replay of the {sys.argv[1]} recording")
        elif int(m.group(2)) < MIN_TICKS:
            failures.append(f"only {m.group(2)} ticks (< {MIN_TICKS})")
        for f in failures:
            print("FAIL " + f)
        if not failures:
            print(f"ok   CASE2 {sys.argv[1]}: {m.group(2)} ticks bit-identical on the host and the Cortex-M4F")
        return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
