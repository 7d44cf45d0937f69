#!/usr/bin/env python3
"""Sessions with dtctune against the twin over real SocketCAN (vcan0; inside User-Mode Linux
where the host kernel has no CAN), as a drive engineer would run them against a board: the
flashable image (build/stm32g4/dtc-fw.elf, byte for byte, with its control tick running) under
`dtc-board exec --can vcan0 --realtime --nvm FILE`, one dtc-board process per power-on.

    test_twin_dtctune.py running DTC_BOARD ELF EDS WORKDIR CASE2_INI
  `dtc-board run` CASE2 (as flashed) with --can vcan0 --realtime: dtctune get, set, read back a
  gain and is refused a stopped-only setting while the emulated motor runs; the run ends on speed.

    test_twin_dtctune.py heartbeat DTC_BOARD ELF EDS WORKDIR CASE2_INI
  `dtc-board run` CASE2 (as shipped, its [control] key in the image's store) with --can vcan0
  --realtime: heartbeat_ms (0x1017) set to 100 while the emulated motor runs; the heartbeat
  frames' receive timestamps on vcan0 (the kernel's, of the listening socket) over at least 3 s
  of wall time give the period: within 5 % of 100 ms. The twin runs faster than real time and
  --realtime holds it to the wall clock, so the bus's timers are in true time; a mean over 30+
  periods does not depend on when the host schedules the process.

    test_twin_dtctune.py tune DTC_BOARD ELF EDS WORKDIR
  get -> set -> get (read back) -> save (0x1010, the firmware's flash store on the twin's flash
  model) -> power-cycle (SIGTERM, new dtc-board on the same --nvm file) -> get = the saved value
  -> restore-defaults (0x1011) -> power-cycle -> get = the EDS default (the python canopen
  package's reading of the EDS, not the firmware's). Every power-on runs the control tick
  (ADC1_2 interrupts > 0) and ends without an emulated reset.

    test_twin_dtctune.py watchdog DTC_BOARD ELF EDS WORKDIR STALL_ELF
  power-on with ELF: reset_cause (0x2510:7) = 1 (power-on), set and save a value; power-on with
  STALL_ELF (the same image built with the test-only hook BOARD_TEST_STALL_TICK_MS: 300 ms after a
  start that was not a watchdog reset its control tick stops; the background keeps running) on
  the same --nvm file. A second node on vcan0 (python-can) sees: boot-up, boot-up again (the
  twin's IWDG reset the MCU: the background alone may not refresh it), then the EMCY 0x6010
  (CiA 301 "software reset (watchdog)"); reset_cause = 4 (watchdog); the saved value is back;
  the control tick runs again and the board is not reset a second time.

Exit status 0 when every step passes."""
import os
import re
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from scenario_as_flashed import as_flashed  # noqa: E402

PARAM = "rbfn_gamma_w"
PARAM_INDEX, PARAM_SUB = 0x2100, 2
RESET_POWER_ON, RESET_WATCHDOG = 1, 4  # reset_cause (0x2510:7), hal.h enum hal_reset_cause
EMCY_WATCHDOG_RESET = 0x6010           # CiA 301 emergency error code "software reset (watchdog)"


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


fails = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        fails.append(what)


def dtctune(eds, *args):
    cmd = [sys.executable, "-m", "dtctune", "--eds", eds, "--timeout", "3", *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    out = (r.stdout + r.stderr).strip()
    print(f"$ dtctune {' '.join(args)}\n{out}  [exit {r.returncode}]", flush=True)
    return r.returncode, out


def value_of(out):
    try:
        return float(out.split()[-1])
    except (ValueError, IndexError):
        return None


def eds_default(eds):
    import canopen
    od = canopen.import_od(eds)
    return float(od[PARAM_INDEX][PARAM_SUB].default)


class Board:
    """One power-on of the emulated board: a dtc-board exec process."""

    def __init__(self, exe, elf, nvm, log):
        self.log = log
        self.f = open(log, "w")
        self.p = subprocess.Popen([exe, "exec", "--elf", elf, "--can", "vcan0", "--can-bitrate", "500000",
                                   "--realtime", "--nvm", nvm, "--seconds", "600", "--stats"],
                                  stderr=self.f, stdout=self.f)
        time.sleep(2.0)  # boot: clocks, ADC calibration, 64 offset periods, CANopen boot-up

    def off(self):
        """Power-off (SIGTERM: the --nvm file is written). @return (exit status, stats text)."""
        self.p.send_signal(signal.SIGTERM)
        rc = self.p.wait(timeout=60)
        self.f.close()
        with open(self.log) as f:
            text = f.read()
        print(text.strip(), flush=True)
        return rc, text


def stats_checks(rc, text, what):
    check(rc == 0, f"{what}: dtc-board exit status {rc}")
    m = re.search(r"control tick \(ADC1_2\): (\d+) interrupts", text)
    check(m is not None and int(m.group(1)) > 100, f"{what}: the image's control tick ran ({m.group(0) if m else 'no count'})")
    m = re.search(r"(\d+) resets", text)
    check(m is not None and int(m.group(1)) == 0, f"{what}: no emulated reset")


def tune(exe, elf, eds, work):
    nvm = os.path.join(work, "twin.nvm")
    if os.path.exists(nvm):
        os.remove(nvm)
    default = eds_default(eds)
    b = Board(exe, elf, nvm, os.path.join(work, "power-on-1.log"))
    try:
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == default, f"first power-on: {PARAM} is the EDS default {default:g}")
        rc, out = dtctune(eds, "get", "reset_cause")
        check(rc == 0 and value_of(out) == RESET_POWER_ON, "reset_cause 1 (power-on)")
        new = default + 250.0
        rc, out = dtctune(eds, "set", PARAM, f"{new:g}")
        check(rc == 0, f"set {PARAM} {new:g}")
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == new, f"read back {PARAM} = {new:g}")
        rc, out = dtctune(eds, "save")
        check(rc == 0, "save (0x1010)")
    finally:
        stats_checks(*b.off(), "power-on 1")
    check(os.path.exists(nvm), "NVM file written at power-off")

    b = Board(exe, elf, nvm, os.path.join(work, "power-on-2.log"))
    try:
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == new, f"after a power cycle {PARAM} = the saved {new:g}")
        rc, out = dtctune(eds, "restore-defaults")
        check(rc == 0, "restore-defaults (0x1011)")
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == default, f"after the restore {PARAM} = the default {default:g}")
    finally:
        stats_checks(*b.off(), "power-on 2")

    b = Board(exe, elf, nvm, os.path.join(work, "power-on-3.log"))
    try:
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == default, f"after another power cycle {PARAM} = the default {default:g}")
        rc, out = dtctune(eds, "get", "persist_status")
        check(rc == 0 and value_of(out) == 0, "persist_status 0: a stored set (the empty one) was loaded")
    finally:
        stats_checks(*b.off(), "power-on 3")


def wait_heartbeats(n, wall_timeout_s):
    """Count heartbeat frames (0x701..0x77F, one byte, not the boot-up's 0x00) on vcan0
    until @p n are seen or @p wall_timeout_s pass. @return how many were seen."""
    import can
    bus = can.Bus(interface="socketcan", channel="vcan0")
    seen = 0
    try:
        deadline = time.monotonic() + wall_timeout_s
        while seen < n and time.monotonic() < deadline:
            m = bus.recv(timeout=0.5)
            if m is not None and 0x701 <= m.arbitration_id <= 0x77F and len(m.data) == 1 and m.data[0] != 0:
                seen += 1
    finally:
        bus.shutdown()
    return seen


def watchdog(exe, elf, eds, work, stall_elf):
    import can
    nvm = os.path.join(work, "twin.nvm")
    if os.path.exists(nvm):
        os.remove(nvm)
    default = eds_default(eds)
    new = default + 500.0
    b = Board(exe, elf, nvm, os.path.join(work, "power-on-1.log"))
    try:
        rc, out = dtctune(eds, "get", "reset_cause")
        check(rc == 0 and value_of(out) == RESET_POWER_ON, "power-on: reset_cause 1 (power-on)")
        rc, out = dtctune(eds, "set", PARAM, f"{new:g}")
        check(rc == 0, f"set {PARAM} {new:g}")
        rc, out = dtctune(eds, "save")
        check(rc == 0, "save (0x1010)")
    finally:
        stats_checks(*b.off(), "power-on 1")

    bus = can.Bus(interface="socketcan", channel="vcan0")
    frames = []
    b = Board(exe, stall_elf, nvm, os.path.join(work, "power-on-stall.log"))
    try:
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline:
            m = bus.recv(timeout=0.5)
            if m is None:
                continue
            frames.append((m.arbitration_id, bytes(m.data)))
            print(f"  bus: {m.arbitration_id:03X} [{len(m.data)}] {bytes(m.data).hex(' ')}", flush=True)
            if 0x081 <= m.arbitration_id <= 0x0FF and len(m.data) == 8:
                break
        bus.shutdown()
        boots = [i for i, (cid, d) in enumerate(frames) if 0x701 <= cid <= 0x77F and d == b"\x00"]
        emcy = [i for i, (cid, d) in enumerate(frames) if 0x081 <= cid <= 0x0FF and len(d) == 8]
        check(len(boots) == 2, f"two boot-up messages: power-on and after the watchdog reset ({len(boots)})")
        code = int.from_bytes(frames[emcy[0]][1][0:2], "little") if emcy else None
        check(emcy and code == EMCY_WATCHDOG_RESET, f"EMCY 0x6010 on the bus (code {code:#06x})" if emcy else "EMCY on the bus")
        check(len(boots) == 2 and emcy and boots[1] < emcy[0], "the EMCY follows the second boot-up")
        rc, out = dtctune(eds, "get", "reset_cause")
        check(rc == 0 and value_of(out) == RESET_WATCHDOG, "reset_cause 4 (independent watchdog)")
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == new, f"after the watchdog reset {PARAM} = the saved {new:g}")
        rc, out = dtctune(eds, "get", "persist_status")
        check(rc == 0 and value_of(out) == 0, "persist_status 0 (the stored set loaded)")
        # Run on for at least one heartbeat period (1 s) of EMULATED time, long past the
        # 0.3 s after which a tick that stalled again would reset again: two heartbeats
        # after this point are at least one period apart. A wall-clock sleep did not
        # measure that (the emulator runs at 0.07-0.2x real time under UML, machine-dependent).
        hb = wait_heartbeats(2, wall_timeout_s=120.0)
        check(hb == 2, f"two heartbeats after the checks ({hb}): at least 1 s more of emulated time")
    finally:
        rc, text = b.off()
    check(rc == 0, f"stall image: dtc-board exit status {rc}")
    m = re.search(r"([\d.]+) s simulated.* (\d+) resets", text)
    check(m is not None and int(m.group(2)) == 1, "exactly one emulated reset (by the IWDG)")
    check(m is not None and float(m.group(1)) > 1.0, f"ran {m.group(1) if m else '?'} s of emulated time (> 1 s)")
    t = re.search(r"control tick \(ADC1_2\): (\d+) interrupts", text)
    sim = float(m.group(1)) if m else 0.0
    # before the stall at most 0.3 s of ticks (1500); afterwards the tick runs to the end
    check(t is not None and int(t.group(1)) > 1500 + 5000 * (sim - 0.3 - 0.1 - 0.1) * 0.9,
          f"the control tick runs again after the reset ({t.group(1) if t else '?'} interrupts in {sim:.2f} s)")


def running(exe, elf, eds, work, case2):
    """Tuning while the emulated motor runs: dtc-board run CASE2 (as flashed: no [control] keys,
    the plant with the 1 V device drop the firmware compensates) with the image's FDCAN1 on vcan0;
    dtctune reads, sets and reads back a parameter during the run; SIGINT then ends the run
    (as Ctrl-C does), which stops cleanly, on speed, without a fault, and writes its metrics."""
    import json
    flashed = as_flashed(case2, os.path.join(work, "case2_as_flashed.ini"))
    metrics = os.path.join(work, "running.json")
    if os.path.exists(metrics):
        os.remove(metrics)
    log = open(os.path.join(work, "running.log"), "w")
    # Long enough for every command however slowly a busy machine starts them (each dtctune is a
    # new process inside User-Mode Linux); SIGINT ends the run once they are done, outputs written.
    p = subprocess.Popen([exe, "run", flashed, "--elf", elf, "--can", "vcan0", "--realtime", "--metrics", metrics,
                          "--set", "sim.duration_s=120"], stdout=log, stderr=log)
    try:
        time.sleep(3.0)  # boot and the start of the run
        check(p.poll() is None, "dtc-board run is running")
        default = eds_default(eds)
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == default, f"while running: {PARAM} is the EDS default {default:g}")
        new = default + 250.0
        rc, out = dtctune(eds, "set", PARAM, f"{new:g}")
        check(rc == 0, f"while running: set {PARAM} {new:g} (a gain: changes within its step while running)")
        rc, out = dtctune(eds, "get", PARAM)
        check(rc == 0 and value_of(out) == new, f"while running: read back {PARAM} = {new:g}")
        rc, out = dtctune(eds, "get", "obs_k_gain")
        check(rc == 0 and value_of(out) is not None, "while running: an observer setting reads")
        rc, out = dtctune(eds, "set", "obs_k_gain", "2")
        check(rc != 0 and "0x08000022" in out.lower(), "while running: a stopped-only setting is refused (0x08000022)")
        check(p.poll() is None, "dtc-board run still running after the commands")
        p.send_signal(signal.SIGINT)
        p.wait(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
        log.close()
    with open(os.path.join(work, "running.log")) as f:
        text = f.read()
    print(text.strip(), flush=True)
    check(p.returncode == 0, f"dtc-board run exit status {p.returncode}")
    if os.path.exists(metrics):
        with open(metrics) as f:
            m = json.load(f)
        check(m["faults"] == 0, f"no fault during the run (0x{m['faults']:x})")
        check(abs(m["speed_final_rpm"] - 500.0) < 10.0, f"CASE2 ended on speed ({m['speed_final_rpm']:.1f} rpm)")
    else:
        check(False, "metrics written")


HEARTBEAT_MS = 100


def heartbeat(exe, elf, eds, work, case2):
    import can
    log = open(os.path.join(work, "heartbeat.log"), "w")
    bus = can.Bus(interface="socketcan", channel="vcan0")
    p = subprocess.Popen([exe, "run", case2, "--elf", elf, "--can", "vcan0", "--realtime",
                          "--set", "sim.duration_s=8"], stdout=log, stderr=log)
    stamps = []
    try:
        time.sleep(2.5)  # boot and the start of the run
        check(p.poll() is None, "dtc-board run is running")
        rc, out = dtctune(eds, "set", "heartbeat_ms", str(HEARTBEAT_MS))
        check(rc == 0, f"while running: set heartbeat_ms (0x1017) {HEARTBEAT_MS}")
        set_at = time.time()
        while p.poll() is None:
            m = bus.recv(timeout=0.5)
            if m is not None and 0x701 <= m.arbitration_id <= 0x77F and len(m.data) == 1 and m.data[0] != 0:
                if m.timestamp > set_at + 0.3:  # past the period that was running when it was set
                    stamps.append(m.timestamp)
        p.wait(timeout=60)
    finally:
        bus.shutdown()
        if p.poll() is None:
            p.kill()
            p.wait()
        log.close()
    with open(os.path.join(work, "heartbeat.log")) as f:
        log_text = f.read().strip()
    print(log_text, flush=True)
    check(p.returncode == 0, f"dtc-board run exit status {p.returncode}")
    # --realtime can only hold emulated time to the wall clock when the twin runs at least as
    # fast as real time; slower (User-Mode Linux on a slow or busy machine), the bus's period
    # measures the emulator's speed, not the pacing: skipped, with the ratio said.
    ratio = re.search(r"\(([0-9.]+) x real time", log_text)
    if ratio and float(ratio.group(1)) < 0.98:
        print(f"skipped: the twin ran at {ratio.group(1)} x real time here, too slow for --realtime to pace", flush=True)
        return 77
    n = len(stamps)
    window = stamps[-1] - stamps[0] if n >= 2 else 0.0
    check(n >= 31 and window >= 3.0, f"{n} heartbeats over {window:.2f} s of bus time (>= 31 over >= 3 s)")
    if n >= 2:
        period = window / (n - 1)
        gaps = [b - a for a, b in zip(stamps, stamps[1:])]
        print(f"heartbeat period {period * 1e3:.2f} ms mean, gaps {min(gaps) * 1e3:.1f}..{max(gaps) * 1e3:.1f} ms", flush=True)
        check(abs(period - HEARTBEAT_MS * 1e-3) <= 0.05 * HEARTBEAT_MS * 1e-3,
              f"heartbeat period on the bus {period * 1e3:.2f} ms = 0x1017 {HEARTBEAT_MS} ms +- 5 %")


def main():
    if len(sys.argv) >= 2 and sys.argv[1] in ("running", "heartbeat"):
        if len(sys.argv) != 7:
            sys.exit(__doc__)
        exe, elf, eds, work, case2 = sys.argv[2:7]
        if not os.path.exists(elf):
            print(f"skipped: {elf} not built (cmake --preset stm32g4 && cmake --build --preset stm32g4)")
            return 77
        os.makedirs(work, exist_ok=True)
        allow_overcommit()
        if (running if sys.argv[1] == "running" else heartbeat)(exe, elf, eds, work, case2) == 77 and not fails:
            return 77
        for f in fails:
            print("FAIL:", f)
        print(f"twin {sys.argv[1]} session:", "ok" if not fails else f"{len(fails)} failure(s)")
        return 1 if fails else 0
    if len(sys.argv) < 6 or sys.argv[1] not in ("tune", "watchdog") or (sys.argv[1] == "watchdog") != (len(sys.argv) == 7):
        sys.exit(__doc__)
    mode, exe, elf, eds, work = sys.argv[1:6]
    for image in sys.argv[3:4] + sys.argv[6:7]:
        if not os.path.exists(image):
            print(f"skipped: {image} not built (cmake --preset stm32g4 && cmake --build --preset stm32g4)")
            return 77
    os.makedirs(work, exist_ok=True)
    allow_overcommit()
    if mode == "tune":
        tune(exe, elf, eds, work)
    else:
        watchdog(exe, elf, eds, work, sys.argv[6])
    for f in fails:
        print("FAIL:", f)
    print(f"twin {mode} session:", "ok" if not fails else f"{len(fails)} failure(s)")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
