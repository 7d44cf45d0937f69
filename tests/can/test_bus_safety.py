"""The drive on a hostile or failing bus, over real SocketCAN (vcan0, inside User-Mode Linux via
tests/can/run_python_test.sh --uml; ctest `can.uml_bus_safety`), judged from the plant's TRUE
speed and torque in dtc-sim's CSV trace (columns t_s, speed_rpm, te_nm, state), not from what the
drive reports.

- malformed frames, NMT pre-operational and back, then the master's heartbeat lost:
  the motor is brought to a stop by the quick stop ramp (abort connection option 0x6007 = 3);
- NMT stop while running: the same reaction, and nothing on the bus is answered afterwards;
- NMT reset-node while running: the boot-up message comes only once the motor has stopped;
- the canopen package's BaseNode402 drives the CiA 402 state machine: switch on disabled ->
  operation enabled -> quick stop -> fault (master lost with 0x6007 = 1) -> fault reset.

Environment: DTC_SIM, DTC_EDS, DTC_CAN_OUT (as tests/can/test_integration.py).
"""
from __future__ import annotations

import csv
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import can
import canopen
import pytest

from dtctune.sil import Sil

REPO = Path(__file__).resolve().parents[2]
CHANNEL = "vcan0"
NODE = 1
MASTER = 0x7F
EDS = Path(os.environ.get("DTC_EDS", REPO / "build" / "host" / "drive.eds"))
SIM = Path(os.environ.get("DTC_SIM", REPO / "build" / "host" / "bin" / "dtc-sim"))
OUT = Path(os.environ.get("DTC_CAN_OUT") or tempfile.mkdtemp(prefix="dtc-bus-"))
OUT.mkdir(parents=True, exist_ok=True)

# 500 rpm: the ramp ends at 1.3 s of case1.ini; everything below happens after 2 s.
SCENARIO = REPO / "host_sim" / "scenarios" / "case1.ini"
STOPPED_RPM = 40.0      # the quick stop ends at 20 rpm (estimate), the motor then coasts
STOP_WITHIN_S = 1.6     # 500 rpm at 900 rpm/s = 0.56 s, + loop lag 0.2 s + final approach + UML jitter


class Run:
    """dtc-sim in real time on vcan0 with a CSV trace, and a raw socket as the master."""

    def __init__(self, name: str):
        self.csv = OUT / f"{name}.csv"
        if self.csv.exists():
            self.csv.unlink()
        self.sil = Sil(channel=CHANNEL, node_id=NODE, sim=SIM, scenario=SCENARIO,
                       extra=["--csv", str(self.csv), "--set", "sim.trace_interval_s=0.002"],
                       log=str(OUT / f"{name}.log"))
        self.bus = None
        self.t0 = 0.0

    def __enter__(self):
        self.bus = can.Bus(interface="socketcan", channel=CHANNEL)
        self.sil.start()
        # The simulated clock starts with the boot-up message (the first background pass), not
        # when the process is spawned: starting dtc-sim takes 0.05-0.3 s in a loaded UML, and
        # a clock counted from the spawn ran that far ahead of the trace's t_s.
        self.t0 = time.monotonic()
        return self

    def __exit__(self, *exc):
        self.sil.stop()
        self.bus.shutdown()

    def now(self) -> float:
        """Seconds since dtc-sim's boot-up: its simulated time runs with the wall clock."""
        return time.monotonic() - self.t0

    def send(self, cob: int, data: bytes):
        self.bus.send(can.Message(arbitration_id=cob, data=data, is_extended_id=False))

    def sdo_write(self, index: int, sub: int, value: int, size: int) -> bytes:
        cmd = {1: 0x2F, 2: 0x2B, 4: 0x23}[size]
        self.drain()
        self.send(0x600 + NODE, bytes([cmd, index & 0xFF, index >> 8, sub]) + value.to_bytes(4, "little"))
        return self.wait_for(0x580 + NODE, 1.0)

    def drain(self):
        """Forget what was received so far (the start-up boot-up message among it). Bounded in
        time: with telemetry flowing, frames may arrive as fast as a loaded UML reads them."""
        end = time.monotonic() + 1.0
        while time.monotonic() < end and self.bus.recv(0.0) is not None:
            pass

    def wait_for(self, cob: int, timeout_s: float, data: bytes | None = None):
        """The data of the first frame on `cob` (with exactly `data`, if given), or None."""
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            msg = self.bus.recv(0.05)
            if msg is not None and msg.arbitration_id == cob and (data is None or bytes(msg.data) == data):
                return bytes(msg.data)
        return None

    def sleep_sending(self, seconds: float, heartbeat: bool, garbage: bool = False):
        """Wait, sending the master's heartbeat every 100 ms and, if asked, malformed frames."""
        rng = random.Random(7)
        end = time.monotonic() + seconds
        next_hb = time.monotonic()
        while time.monotonic() < end:
            if heartbeat and time.monotonic() >= next_hb:
                self.send(0x700 + MASTER, b"\x05")
                next_hb += 0.1
            if garbage:
                cob = rng.choice([0x000, 0x200 + NODE, 0x600 + NODE, rng.randrange(0x800)])
                data = bytes(rng.randrange(256) for _ in range(rng.randrange(9)))
                if cob == 0x000 and len(data) == 2 and data[0] in (0x01, 0x02, 0x80, 0x81, 0x82):
                    data = bytes([data[0], 0x55])  # NMT for another node only
                if cob == 0x600 + NODE and len(data) == 8 and data[0] >> 5 in (0, 1):
                    data = bytes([0x40]) + data[1:]  # uploads only: nothing may change
                if cob == 0x200 + NODE:
                    data = data[:3]  # too short to be applied
                self.send(cob, data)
            time.sleep(0.005)

    def trace(self):
        with open(self.csv, newline="") as f:
            rows = list(csv.DictReader(f))
        assert rows, "empty trace"
        return [(float(r["t_s"]), float(r["speed_rpm"]), float(r["te_nm"]), int(r["state"])) for r in rows]


def at(rows, t: float):
    for r in rows:
        if r[0] >= t:
            return r
    return rows[-1]


def first_stop(rows, after: float):
    """First time after `after` where the controller reports stopped (state 0) or faulted (3)."""
    for r in rows:
        if r[0] >= after and r[3] in (0, 3):
            return r[0]
    return None


def start_master(r: Run, heartbeat_ms: int = 300):
    """Operational, the master's heartbeat watched."""
    r.send(0x000, bytes([0x01, NODE]))
    rsp = r.sdo_write(0x1016, 1, (MASTER << 16) | heartbeat_ms, 4)
    assert rsp is not None and rsp[0] == 0x60, rsp


def test_hostile_traffic_then_heartbeat_lost_stops_the_motor():
    with Run("hostile") as r:
        start_master(r)
        r.sleep_sending(2.0 - r.now(), heartbeat=True, garbage=True)
        r.send(0x000, bytes([0x80, NODE]))  # pre-operational: SDO still works, the motor keeps running
        r.sleep_sending(0.5, heartbeat=True, garbage=True)
        r.send(0x000, bytes([0x01, NODE]))
        r.sleep_sending(0.5, heartbeat=True, garbage=True)
        t_lost = r.now()  # the master goes silent
        r.sleep_sending(3.0, heartbeat=False)
    rows = r.trace()
    assert at(rows, t_lost - 0.05)[1] == pytest.approx(500.0, abs=15.0), "ran through the hostile traffic"
    t_stop = first_stop(rows, t_lost)
    assert t_stop is not None, "the motor was not stopped after the heartbeat was lost"
    assert t_lost + 0.3 - 0.1 < t_stop < t_lost + 0.3 + STOP_WITHIN_S, (t_lost, t_stop)
    assert abs(at(rows, t_stop)[1]) < STOPPED_RPM
    assert abs(rows[-1][1]) < STOPPED_RPM and abs(rows[-1][2]) < 1.0, rows[-1]
    # A controlled ramp, not a coast: half a second into the reaction the speed is well down.
    assert at(rows, t_lost + 0.3 + 0.5)[1] < 350.0


def test_nmt_stop_while_running_stops_the_motor_and_the_node_stays_silent():
    with Run("nmt_stop") as r:
        r.send(0x000, bytes([0x01, NODE]))
        time.sleep(max(0.0, 2.0 - r.now()))
        t_cmd = r.now()
        r.send(0x000, bytes([0x02, NODE]))
        time.sleep(0.3)
        r.drain()
        r.send(0x600 + NODE, bytes([0x40, 0x41, 0x60, 0, 0, 0, 0, 0]))
        answered = r.wait_for(0x580 + NODE, 0.5)
        time.sleep(2.0)
    rows = r.trace()
    assert answered is None, "an SDO was answered in NMT stopped"
    assert at(rows, t_cmd - 0.05)[1] == pytest.approx(500.0, abs=15.0)
    t_stop = first_stop(rows, t_cmd)
    assert t_stop is not None and t_stop < t_cmd + STOP_WITHIN_S, (t_cmd, t_stop)
    assert abs(rows[-1][1]) < STOPPED_RPM


def test_nmt_reset_while_running_stops_the_motor_before_the_reset():
    with Run("nmt_reset") as r:
        r.send(0x000, bytes([0x01, NODE]))
        time.sleep(max(0.0, 2.0 - r.now()))
        r.drain()
        t_cmd = r.now()
        r.send(0x000, bytes([0x81, 0]))
        boot = r.wait_for(0x700 + NODE, STOP_WITHIN_S + 1.0, data=b"\x00")  # not a heartbeat
        t_boot = r.now()
        time.sleep(0.3)
    rows = r.trace()
    assert boot == b"\x00", "no boot-up after the reset"
    assert t_boot > t_cmd + 0.3, "reset at once, the motor still turning"
    assert abs(at(rows, t_boot - 0.05)[1]) < STOPPED_RPM + 20.0, (t_boot, at(rows, t_boot))


def test_basenode402_drives_the_state_machine():
    with Run("node402") as r:
        net = canopen.Network()
        net.connect(interface="socketcan", channel=CHANNEL)
        try:
            node = canopen.BaseNode402(NODE, str(EDS))
            net.add_node(node)
            node.sdo.RESPONSE_TIMEOUT = 1.0
            node.nmt.state = "OPERATIONAL"
            node.sdo[0x2500][3].raw = 100  # telemetry_hz: the statusword comes by TPDO 4
            node.setup_402_state_machine()
            node.op_mode = "VELOCITY"
            assert node.op_mode == "VELOCITY"
            node.state = "SWITCH ON DISABLED"
            time.sleep(0.3)
            assert node.state == "SWITCH ON DISABLED"
            # dtc-sim's own reference ramp (case1.ini, to 500 rpm at 1.3 s) must be over first.
            time.sleep(max(0.0, 1.5 - r.now()))
            # RPDO 1 carries the controlword with the target velocity (0x60FF): set the
            # master's copy so every controlword BaseNode402 sends carries 300 rpm.
            node.rpdo_pointers[0x60FF].raw = 300
            node.state = "OPERATION ENABLED"
            assert node.sdo[0x6042].raw == 300  # the vl target shows the same reference
            time.sleep(1.5)
            t_qs = r.now()
            node.state = "QUICK STOP ACTIVE"
            deadline = time.monotonic() + STOP_WITHIN_S + 1.0
            while node.state != "SWITCH ON DISABLED" and time.monotonic() < deadline:
                time.sleep(0.05)
            assert node.state == "SWITCH ON DISABLED", "the quick stop did not end"
            # Fault: the master's heartbeat lost with the abort connection option 1 (fault).
            node.sdo[0x6007].raw = 1
            node.sdo[0x1016][1].raw = (MASTER << 16) | 200
            node.state = "OPERATION ENABLED"
            r.sleep_sending(0.5, heartbeat=True)
            t_fault = r.now()
            # The communication error also sends the node to pre-operational (0x1029 = 0):
            # no TPDOs, so the statusword is read by SDO until the master restarts it.
            deadline = time.monotonic() + 2.0
            while node.sdo[0x6041].raw & 0x4F != 0x08 and time.monotonic() < deadline:
                time.sleep(0.05)
            assert node.sdo[0x6041].raw & 0x4F == 0x08, "not in the fault state"
            assert node.nmt.wait_for_heartbeat(timeout=1.5) == "PRE-OPERATIONAL"
            node.sdo[0x1016][1].raw = 0
            node.nmt.state = "OPERATIONAL"
            time.sleep(0.2)  # TPDOs again
            assert node.state == "FAULT"
            node.state = "SWITCH ON DISABLED"  # fault reset (rising edge of bit 7)
            assert node.state == "SWITCH ON DISABLED"
        finally:
            net.disconnect()
    rows = r.trace()
    assert at(rows, t_qs - 0.05)[1] == pytest.approx(300.0, abs=15.0), "operation enabled at 300 rpm"
    t_stop = first_stop(rows, t_qs)
    assert t_stop is not None and t_stop < t_qs + STOP_WITHIN_S
    assert first_stop(rows, t_fault) is not None


def dtctune_cli(*args):
    """The dtctune command line, as a user runs it: (status, stdout, stderr)."""
    exe = shutil.which("dtctune", path=str(Path(sys.executable).parent)) or shutil.which("dtctune")
    cmd = ([exe] if exe else [sys.executable, "-m", "dtctune"]) + \
        ["--channel", CHANNEL, "--node", str(NODE), "--eds", str(EDS), "--timeout", "2.0"] + list(args)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    return r.returncode, r.stdout.strip(), r.stderr.strip()


def state_cli(*args):
    st, out, err = dtctune_cli("state", *args)
    assert st == 0, "dtctune state %s -> %d: %s %s" % (" ".join(args), st, out, err)
    return out


def test_dtctune_state_commands_drive_the_state_machine():
    """The same walk as BaseNode402's above, with `dtctune state`: disable, enable (the motor
    at the bus's 300 rpm), quick stop (the motor stops within the quick stop's time), a fault
    (the master lost with 0x6007 = 1) and its reset; each printed state is the statusword's."""
    with Run("dtctune_state") as r:
        assert state_cli("disable").startswith("SWITCH ON DISABLED")
        assert state_cli().startswith("SWITCH ON DISABLED")
        assert "nothing to stop" in state_cli("quick-stop")
        assert "nothing to reset" in state_cli("fault-reset")
        time.sleep(max(0.0, 1.5 - r.now()))  # case1.ini's own ramp to 500 rpm over first
        assert dtctune_cli("set", "target_velocity", "300")[0] == 0
        assert state_cli("enable").startswith("OPERATION ENABLED")
        time.sleep(1.5)
        # the controlword goes out between these two instants (a new process: in a busy User-Mode
        # Linux it may take a second or two to start); the stop is judged from the later one
        t_before = r.now()
        out = state_cli("quick-stop")
        t_qs = r.now()
        assert out.startswith("QUICK STOP ACTIVE") or out.startswith("SWITCH ON DISABLED"), out
        deadline = time.monotonic() + STOP_WITHIN_S + 1.0
        while not state_cli().startswith("SWITCH ON DISABLED") and time.monotonic() < deadline:
            time.sleep(0.1)
        assert state_cli().startswith("SWITCH ON DISABLED"), "the quick stop did not end"
        # a fault: the master's heartbeat lost with the abort connection option 1 (fault)
        assert dtctune_cli("set", "abort_connection_option", "1")[0] == 0
        assert dtctune_cli("set", "hb_consumer", str((MASTER << 16) | 200))[0] == 0
        assert state_cli("enable").startswith("OPERATION ENABLED")
        r.sleep_sending(0.5, heartbeat=True)
        t_fault = r.now()
        deadline = time.monotonic() + 3.0
        while not state_cli().startswith("FAULT") and time.monotonic() < deadline:
            time.sleep(0.1)
        assert state_cli().startswith("FAULT"), "not in the fault state"
        assert dtctune_cli("set", "hb_consumer", "0")[0] == 0
        assert state_cli("fault-reset").startswith("SWITCH ON DISABLED")
    rows = r.trace()
    assert at(rows, t_before - 0.05)[1] == pytest.approx(300.0, abs=15.0), "operation enabled at 300 rpm"
    t_stop = first_stop(rows, t_before)
    assert t_stop is not None and t_stop < t_qs + STOP_WITHIN_S
    assert first_stop(rows, t_fault) is not None


# ----------------------------------------------------------------------------- bus-off
CAN_ERR_BUSOFF = 0x040      # linux/can/error.h: bus off (in the error frame's identifier)
CAN_ERR_RESTARTED = 0x100   # controller restarted


def test_bus_off_error_frame_quick_stops_and_emcy_after_the_restart():
    """The controller's bus-off as SocketCAN reports it (an error frame with CAN_ERR_BUSOFF,
    here sent on vcan0 where no real controller can go bus-off), then its restart
    (CAN_ERR_RESTARTED): the 0x6007 reaction (quick stop) judged from the plant's true speed,
    and EMCY 0x8140 (recovered from bus-off) after the restart, not before."""
    with Run("bus_off") as r:
        r.send(0x000, bytes([0x01, NODE]))
        time.sleep(max(0.0, 2.0 - r.now()))
        r.drain()
        t_off = r.now()
        r.bus.send(can.Message(arbitration_id=CAN_ERR_BUSOFF, is_error_frame=True, is_extended_id=False,
                               data=bytes(8)))
        early = r.wait_for(0x080 + NODE, 0.3)
        t_restart = r.now()
        r.bus.send(can.Message(arbitration_id=CAN_ERR_RESTARTED, is_error_frame=True, is_extended_id=False,
                               data=bytes(8)))
        emcy = r.wait_for(0x080 + NODE, 1.0)
        time.sleep(STOP_WITHIN_S)
    rows = r.trace()
    assert early is None, "an EMCY before the restart: %r" % early
    assert emcy is not None and emcy[0] | (emcy[1] << 8) == 0x8140, emcy
    assert at(rows, t_off - 0.05)[1] == pytest.approx(500.0, abs=15.0)
    t_stop = first_stop(rows, t_off)
    assert t_stop is not None and t_off + 0.2 < t_stop < t_off + STOP_WITHIN_S, (t_off, t_stop)
    assert at(rows, t_off + 0.6)[1] < 350.0, "a ramp, not a coast"
    assert abs(rows[-1][1]) < STOPPED_RPM
    assert t_restart > t_off


# ------------------------------------------------------- error history, block upload
def _emcy_codes(net_log):
    return [e.code for e in net_log]


def test_error_history_read_and_cleared_by_the_canopen_package():
    """0x1003 read through the canopen package's SDO client (an ARRAY in the EDS): sub 0 the
    number of errors, sub 1 the newest; each entry's low 16 bits the EMCY code and bits 23..16
    the error register of the EMCY the package itself received. Writing 1 to sub 0 is refused
    (0x06090030), 0 clears."""
    with Run("errhist") as r:
        net = canopen.Network()
        net.connect(interface="socketcan", channel=CHANNEL)
        try:
            node = canopen.RemoteNode(NODE, str(EDS))
            net.add_node(node)
            node.sdo.RESPONSE_TIMEOUT = 1.0
            node.nmt.state = "OPERATIONAL"
            time.sleep(0.2)
            node.sdo[0x1003][0].raw = 0
            assert node.sdo[0x1003][0].raw == 0
            node.emcy.reset()
            # Two communication errors: a short RPDO (0x8210), then the master's heartbeat lost
            # (0x8130) with no reaction (0x6007 = 0) and no NMT change (0x1029 = 1).
            node.sdo[0x6007].raw = 0
            node.sdo[0x1029][1].raw = 1
            r.send(0x200 + NODE, b"\x0f")
            time.sleep(0.3)
            node.sdo[0x1016][1].raw = (MASTER << 16) | 200
            r.send(0x700 + MASTER, b"\x05")
            time.sleep(0.6)
            node.sdo[0x1016][1].raw = 0
            got = [(e.code, e.register) for e in node.emcy.log if e.code]
            assert [c for c, _ in got] == [0x8210, 0x8130], got
            arr = node.sdo[0x1003]
            n = arr[0].raw
            entries = [arr[i].raw for i in range(1, n + 1)]
            assert n == 2, entries
            assert entries == [c | (reg << 16) for c, reg in reversed(got)], (entries, got)
            with pytest.raises(canopen.SdoAbortedError) as e:
                arr[0].raw = 1
            assert e.value.code == 0x06090030
            assert arr[0].raw == 2, "a refused write changes nothing"
            arr[0].raw = 0
            assert arr[0].raw == 0
        finally:
            net.disconnect()


def test_scope_block_upload_by_the_canopen_package_equals_the_segmented_upload():
    """The scope capture (a DOMAIN of 4 x 1024 REAL32) read by the canopen package's block
    upload client (CRC requested) and by its segmented upload: the same bytes, the size the
    drive announced."""
    from dtctune.od import Dictionary
    dic = Dictionary(EDS, NODE)
    addr = {n: (dic.lookup(n).index, dic.lookup(n).subindex) for n in
            ("scope_command", "scope_state", "scope_trigger", "scope_data",
             "scope_channel_1", "scope_channel_2", "scope_channel_3", "scope_channel_4")}
    with Run("scope_block"):
        net = canopen.Network()
        net.connect(interface="socketcan", channel=CHANNEL)
        try:
            node = canopen.RemoteNode(NODE, str(EDS))
            net.add_node(node)
            node.sdo.RESPONSE_TIMEOUT = 2.0

            def var(name):
                i, s = addr[name]
                return node.sdo[i][s] if s else node.sdo[i]

            var("scope_command").raw = 0
            for k in range(1, 5):
                var("scope_channel_%d" % k).raw = k + 1  # telemetry signals 2..5
            var("scope_trigger").raw = 0
            var("scope_command").raw = 1
            time.sleep(0.5)
            var("scope_command").raw = 2
            deadline = time.monotonic() + 10.0
            while var("scope_state").raw != 3 and time.monotonic() < deadline:
                time.sleep(0.05)
            assert var("scope_state").raw == 3
            i, s = addr["scope_data"]
            with var("scope_data").open("rb", block_transfer=True) as f:
                block = f.read()
            segmented = node.sdo.upload(i, s)
        finally:
            net.disconnect()
    assert len(block) == 4 * 4 * 1024
    assert block == segmented
    vals = struct.unpack("<%df" % (4 * 1024), block)
    assert any(v != 0.0 for v in vals), "a capture of zeros only"


def test_every_sdo_upload_answered_under_1khz_telemetry():
    """Issue 12 found 14 of 200 SDO uploads unanswered with the telemetry at 1 kHz: 200 uploads
    of 0x1000, each answered within 0.5 s, while four TPDOs per cycle flow at 1 kHz. The answers
    are taken from a socket that receives 0x580 + id only (as dtctune's SDO socket does): a
    socket that also receives the 4000 TPDOs/s overflows when the loaded machine does not drain
    it in time, and 11-12 answers were lost there, on the PC side; the TPDOs are counted on
    another socket."""
    from dtctune.od import Dictionary
    p_rate = Dictionary(EDS, NODE).lookup("telemetry_hz")
    with Run("sdo_under_telemetry") as r:
        rsp = r.sdo_write(p_rate.index, p_rate.subindex, 1000, 2)
        assert rsp is not None and rsp[0] == 0x60, rsp
        answers = can.Bus(interface="socketcan", channel=CHANNEL,
                          can_filters=[{"can_id": 0x580 + NODE, "can_mask": 0x7FF}])
        try:
            r.send(0x000, bytes([0x01, NODE]))
            time.sleep(0.5)
            r.drain()
            unanswered = 0
            req = bytes([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0])
            for _ in range(200):
                r.send(0x600 + NODE, req)
                end = time.monotonic() + 0.5
                got = None
                while time.monotonic() < end:
                    msg = answers.recv(0.05)
                    if msg is not None and bytes(msg.data[1:4]) == req[1:4]:
                        got = bytes(msg.data)
                        break
                if got is None:
                    unanswered += 1
                else:
                    assert got[0] == 0x43, got
            # Count what the telemetry socket holds; bounded in time, because the SIL keeps
            # sending 4000 TPDOs/s and a loaded UML may read no faster than they arrive.
            tpdos = 0
            drain_end = time.monotonic() + 2.0
            while time.monotonic() < drain_end:
                msg = r.bus.recv(0.0)
                if msg is None:
                    break
                tpdos += 0x180 <= msg.arbitration_id < 0x580
        finally:
            answers.shutdown()
    assert unanswered == 0
    assert tpdos > 200, "the telemetry was flowing"
