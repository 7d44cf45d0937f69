#!/usr/bin/env python3
"""A tuning session with dtctune against the twin over real SocketCAN (vcan0; inside User-Mode
Linux where the host kernel has no CAN): the real drive + CANopen firmware (canopen_image.elf,
the target's firmware libraries with the port's HAL) runs on the emulated STM32G474 under
`dtc-board exec --can vcan0 --realtime --nvm FILE`.
  get -> set -> get (read back) -> save (0x1010, the firmware's flash store on the twin's
  flash model) -> power-cycle (SIGTERM, new dtc-board process on the same --nvm file) -> get.
    test_twin_dtctune.py DTC_BOARD IMAGE EDS WORKDIR
Exit status 0 when every step passes."""
import os
import signal
import subprocess
import sys
import time

PARAM = "rbfn_gamma_w"


def allow_overcommit():
    """Unicorn 2.0.1 reserves a large translation buffer; the throw-away UML guest (mem=512M)
    refuses it under heuristic overcommit. Only inside the guest."""
    try:
        with open("/proc/cpuinfo") as f:
            if "User Mode Linux" not in f.read():
                return
        with open("/proc/sys/vm/overcommit_memory", "w") as f:
            f.write("1")
    except OSError as e:
        print("note:", e)


def dtctune(eds, *args):
    cmd = [sys.executable, "-m", "dtctune", "--eds", eds, "--timeout", "3", *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    out = (r.stdout + r.stderr).strip()
    print(f"$ dtctune {' '.join(args)}\n{out}  [exit {r.returncode}]", flush=True)
    return r.returncode, out


def power_on(exe, elf, nvm):
    p = subprocess.Popen([exe, "exec", "--elf", elf, "--can", "vcan0", "--can-bitrate", "500000", "--realtime",
                          "--nvm", nvm, "--seconds", "600", "--stats"])
    time.sleep(1.5)  # boot: clocks, drive_init, CANopen boot-up (about 0.1 s of emulated time)
    return p


def power_off(p):
    p.send_signal(signal.SIGTERM)
    return p.wait(timeout=30)


def main():
    exe, elf, eds, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    nvm = os.path.join(work, "twin.nvm")
    if os.path.exists(nvm):
        os.remove(nvm)
    allow_overcommit()
    fails = []
    p = power_on(exe, elf, nvm)
    try:
        rc, before = dtctune(eds, "get", PARAM)
        if rc != 0:
            fails.append(f"get {PARAM}: {before}")
        try:
            new = float(before.split()[-1]) + 250.0
        except (ValueError, IndexError):
            new = 2250.0
        rc, out = dtctune(eds, "set", PARAM, f"{new:g}")
        if rc != 0:
            fails.append(f"set {PARAM} {new:g}: {out}")
        rc, out = dtctune(eds, "get", PARAM)
        if rc != 0 or f"{new:g}" not in out:
            fails.append(f"read back {PARAM}: {out}")
        rc, out = dtctune(eds, "save")
        if rc != 0:
            fails.append(f"save: {out}")
    finally:
        rc = power_off(p)
    if rc != 0:
        fails.append(f"dtc-board (first power-on) exit status {rc}")
    if not os.path.exists(nvm):
        fails.append("no NVM file after power-off")
    p = power_on(exe, elf, nvm)
    try:
        rc, out = dtctune(eds, "get", PARAM)
        if rc != 0 or f"{new:g}" not in out:
            fails.append(f"after power-cycle {PARAM}: {out} (want {new:g})")
    finally:
        rc = power_off(p)
    if rc != 0:
        fails.append(f"dtc-board (second power-on) exit status {rc}")
    for f in fails:
        print("FAIL:", f)
    print("twin tuning session:", "ok" if not fails else f"{len(fails)} failure(s)")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
