"""CAN integration test: the simulated drive (dtc-sim --realtime --can vcan0) tuned over real
SocketCAN with the dtctune command line, as a user would, and checked with the canopen package
against the EDS the build generated.

Runs where vcan0 exists: inside User-Mode Linux via tests/can/run_python_test.sh --uml (ctest
`can.uml_integration`), or directly on a host with vcan0 up.
Environment: DTC_SIM (dtc-sim binary), DTC_EDS (the generated EDS), DTC_CAN_SCENARIO (a
closed-loop scenario, default host_sim/scenarios/case1.ini), DTC_CAN_OUT (where the CSV and
PNG outputs are kept, default a temporary directory).

The expected abort codes and limits come from the EDS text itself (read here with configparser)
and from CiA 301, not from dtctune.
"""
from __future__ import annotations

import configparser
import csv
import os
import re
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
from canopen.sdo.exceptions import SdoAbortedError

from dtctune.sil import Sil

REPO = Path(__file__).resolve().parents[2]
CHANNEL = "vcan0"
NODE = 1
EDS = Path(os.environ.get("DTC_EDS", REPO / "build" / "host" / "drive.eds"))
SIM = Path(os.environ.get("DTC_SIM", REPO / "build" / "host" / "bin" / "dtc-sim"))

ABORT_HIGH = 0x06090031
ABORT_LOW = 0x06090032
ABORT_STATE = 0x08000022

# EDS DataType codes (CiA 306) -> struct format of the value on the bus.
FORMATS = {0x01: "<B", 0x02: "<b", 0x03: "<h", 0x04: "<i", 0x05: "<B", 0x06: "<H", 0x07: "<I", 0x08: "<f"}
INT_RANGE = {0x01: (0, 1), 0x02: (-2**7, 2**7 - 1), 0x03: (-2**15, 2**15 - 1), 0x04: (-2**31, 2**31 - 1),
             0x05: (0, 2**8 - 1), 0x06: (0, 2**16 - 1), 0x07: (0, 2**32 - 1)}


# ----------------------------------------------------------------------------- helpers

def out_dir() -> Path:
    d = os.environ.get("DTC_CAN_OUT")
    p = Path(d) if d else Path(tempfile.mkdtemp(prefix="dtc-can-"))
    p.mkdir(parents=True, exist_ok=True)
    return p


OUT = out_dir()


def dtctune(*args, check=None, timeout=60):
    """Run the dtctune command line; returns (status, stdout, stderr)."""
    exe = shutil.which("dtctune", path=str(Path(sys.executable).parent)) or shutil.which("dtctune")
    cmd = ([exe] if exe else [sys.executable, "-m", "dtctune"]) + \
        ["--interface", "socketcan", "--channel", CHANNEL, "--node", str(NODE), "--eds", str(EDS)] + list(args)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if check is not None:
        assert r.returncode == check, "dtctune %s -> %d\nstdout: %s\nstderr: %s" % (
            " ".join(args), r.returncode, r.stdout, r.stderr)
    if r.returncode != 0:
        lines = [l for l in r.stderr.splitlines() if l.strip()]
        assert len(lines) == 1 and "Traceback" not in r.stderr, "not one error line:\n" + r.stderr
    return r.returncode, r.stdout, r.stderr


def value_of(stdout: str) -> float:
    """`name = 12.5 unit` -> 12.5"""
    m = re.match(r"\s*\S+ = (\S+)", stdout)
    assert m, stdout
    return float(m.group(1))


def eds_entries():
    """Every variable of the EDS as a dict (index, sub, name, dtype, access, low, high)."""
    eds = configparser.RawConfigParser(inline_comment_prefixes=(";",))
    eds.optionxform = str
    eds.read(str(EDS))
    out = []
    for sec in eds.sections():
        m = re.fullmatch(r"([0-9A-Fa-f]{4})(?:sub([0-9A-Fa-f]+))?", sec)
        if not m or int(eds.get(sec, "ObjectType", fallback="0x7"), 0) not in (0x7,):
            continue
        dtype = int(eds.get(sec, "DataType"), 0)
        lim = {}
        for key in ("LowLimit", "HighLimit"):
            if eds.has_option(sec, key):
                text = eds.get(sec, key)
                lim[key] = float(text) if dtype == 0x08 else int(text, 0)
        out.append(dict(index=int(m.group(1), 16), sub=int(m.group(2), 16) if m.group(2) else 0,
                        name=eds.get(sec, "ParameterName"), dtype=dtype,
                        access=eds.get(sec, "AccessType").lower(),
                        low=lim.get("LowLimit"), high=lim.get("HighLimit"),
                        default=eds.get(sec, "DefaultValue", fallback=None)))
    return out


def float32_next(x: float, up: bool) -> float:
    """The neighbouring single-precision value of x (one step outside a REAL32 limit)."""
    b = struct.unpack("<I", struct.pack("<f", x))[0]
    if x == 0.0:
        return struct.unpack("<f", struct.pack("<I", 1 if up else 0x80000001))[0]
    if (x > 0) == up:
        b += 1
    else:
        b -= 1
    return struct.unpack("<f", struct.pack("<I", b))[0]


class Drive:
    """The SIL process, restartable with the same NVM file."""

    def __init__(self):
        self.nvm = str(OUT / "drive.nvm")
        if os.path.exists(self.nvm):
            os.unlink(self.nvm)
        self.sil = None
        self.boots = []

    def start(self):
        self.sil = Sil(CHANNEL, NODE, nvm=self.nvm, sim=SIM, log=str(OUT / "dtc-sim.log"))
        self.boots.append(self.sil.start(timeout_s=30.0))

    def stop(self):
        rc = self.sil.stop() if self.sil else None
        self.sil = None
        return rc


@pytest.fixture(scope="module")
def drive():
    assert EDS.is_file(), "no EDS at %s: build the host preset first" % EDS
    assert SIM.is_file(), "no dtc-sim at %s: build the host preset first" % SIM
    d = Drive()
    d.start()
    yield d
    rc = d.stop()
    assert rc == 0, "dtc-sim ended with status %s (see %s)" % (rc, OUT / "dtc-sim.log")


@pytest.fixture
def network(drive):
    net = canopen.Network()
    net.NOTIFIER_CYCLE = 0.05
    net.connect(interface="socketcan", channel=CHANNEL)
    node = net.add_node(NODE, str(EDS))
    node.sdo.RESPONSE_TIMEOUT = 1.0
    yield net, node
    net.disconnect()


# ----------------------------------------------------------------------------- dtctune as a user

def test_identity_and_list(drive):
    _, out, _ = dtctune("get", "device_type", "--value-only", check=0)
    assert int(out.split()[0]) == 0x00010192  # CiA 402 frequency converter (table: device.device_type)
    _, out, _ = dtctune("list", check=0)
    names = [l.split()[0] for l in out.splitlines()[1:]]
    assert "rbfn_gamma_w" in names and "telemetry_hz" in names and "tel_speed_est_rpm" in names


def test_the_tool_alone_with_its_packaged_eds_reads_the_drive(drive, tmp_path):
    """dtctune as a PC next to a board has it: the package copied out of the checkout (no build
    tree, no --eds, no $DTCTUNE_EDS), run from a directory outside it. It takes its packaged EDS,
    the drive's dictionary signature (0x2510:8) fits it, and the read works."""
    pkg = tmp_path / "site"
    shutil.copytree(REPO / "tools" / "dtctune", pkg / "dtctune",
                    ignore=shutil.ignore_patterns("tests", "__pycache__"))
    env = {k: v for k, v in os.environ.items() if k != "DTCTUNE_EDS"}
    env["PYTHONPATH"] = str(pkg)
    r = subprocess.run([sys.executable, "-m", "dtctune", "--channel", CHANNEL, "--node", str(NODE),
                        "get", "rbfn_gamma_w"], capture_output=True, text=True, timeout=60, cwd=str(tmp_path),
                       env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "rbfn_gamma_w = 4000.0", r.stdout


def test_set_and_read_back_a_gain(drive):
    _, out, _ = dtctune("set", "rbfn_gamma_w", "2500", check=0)
    assert value_of(out) == 2500.0
    _, out, _ = dtctune("get", "rbfn_gamma_w", check=0)
    assert value_of(out) == 2500.0


def test_out_of_range_refused_with_abort_code_and_unchanged(drive):
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    before = value_of(out)
    # dtctune itself refuses (range from the EDS), nothing sent
    status, _, err = dtctune("set", "rbfn_k", "1000.5")
    assert status == 2 and "outside the range" in err
    # sent anyway: the drive refuses with CiA 301 abort codes, dtctune says so in words
    status, _, err = dtctune("set", "--no-check", "rbfn_k", "1000.5")
    assert status == 4 and "value too high (0x06090031)" in err, err
    status, _, err = dtctune("set", "--no-check", "rbfn_k", "0.05")
    assert status == 4 and "value too low (0x06090032)" in err, err
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    assert value_of(out) == before


def test_not_while_running_refused_in_words(drive):
    # rbfn_n_nodes may not change while the motor runs (table: runtime = false)
    status, _, err = dtctune("set", "rbfn_n_nodes", "4")
    assert status == 4 and "0x08000022" in err and "present state" in err, err


def test_unknown_name_and_timeout_are_one_line(drive):
    status, _, err = dtctune("get", "rbfn_gama_w")
    assert status == 2 and "did you mean rbfn_gamma_w" in err
    status, _, err = dtctune("--node", "5", "--timeout", "0.3", "get", "rbfn_k")
    assert status == 3 and "timeout" in err


def test_save_survives_restart_unsaved_does_not(drive):
    # Gains move in bounded steps while the motor runs (max_step): +20 % and -20 %.
    dtctune("set", "rbfn_k", "24", check=0)
    dtctune("save", check=0)
    _, out, _ = dtctune("get", "ip_zeta", check=0)
    zeta_saved = value_of(out)
    dtctune("set", "ip_zeta", "0.8", check=0)  # changed after the save: must be lost
    assert drive.stop() == 0
    drive.start()
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    assert value_of(out) == 24.0
    _, out, _ = dtctune("get", "ip_zeta", check=0)
    assert value_of(out) == zeta_saved
    _, out, _ = dtctune("get", "rbfn_gamma_w", check=0)
    assert value_of(out) == 2500.0  # set before the save: persisted too


@pytest.mark.parametrize("rate_hz", [100, 1000])
def test_record_telemetry_rate(drive, rate_hz):
    dtctune("set", "telemetry_hz", str(rate_hz), check=0)
    dest = OUT / ("record_%d.csv" % rate_hz)
    seconds = 3.0
    _, out, _ = dtctune("get", "tpdo_dropped", "--value-only", check=0)
    dropped0 = int(out.split()[0])
    _, out, _ = dtctune("record", "--start", "--seconds", str(seconds), "--csv", str(dest), check=0, timeout=90)
    print(out.strip())
    _, out2, _ = dtctune("get", "tpdo_dropped", "--value-only", check=0)
    tx_dropped = int(out2.split()[0]) - dropped0
    with open(dest) as f:
        rows = list(csv.DictReader(f))
    assert rows, out
    # one row per telemetry cycle (all TPDOs of a cycle): rate from the receive timestamps
    t = [float(r["t_s"]) for r in rows]
    rate = (len(rows) - 1) / (t[-1] - t[0])
    # The SIL paces itself to the wall clock as well as the machine lets it; dtctune reports the
    # drive's own clock (its tick counter) over the recording, so the rate is checked in the
    # drive's time always, and in wall-clock time when the SIL kept (nearly) real time.
    m = re.search(r"drive clock: ([\d.]+) s in ([\d.]+) s of wall time \(the drive ran at ([\d.]+)x", out)
    assert m, out
    realtime = float(m.group(3))
    print("telemetry %d Hz: %.1f Hz wall clock, %.1f Hz drive clock, SIL at %.3fx real time"
          % (rate_hz, rate, rate / realtime, realtime))
    assert rate / realtime == pytest.approx(rate_hz, rel=0.10), \
        "%.1f Hz in the drive's time for %d Hz" % (rate / realtime, rate_hz)
    if realtime >= 0.9:
        assert rate == pytest.approx(rate_hz, rel=0.10), "measured %.1f Hz for %d Hz" % (rate, rate_hz)
    else:
        import warnings
        warnings.warn("the SIL ran at %.2fx real time (machine busy): wall-clock rate %.1f Hz not checked"
                      % (realtime, rate))
    # the drive's cycle counter: consecutive, so no cycle was lost
    seq = [int(r["pdo_seq"]) for r in rows if r["pdo_seq"] != ""]
    gaps = sum(((b - a) % 65536) - 1 for a, b in zip(seq, seq[1:]))
    assert gaps == 0, "%d telemetry cycles lost (%d frames refused by the drive's transmit queue%s)" % (
        gaps, tx_dropped, "; " + out.split("warning: ")[1].strip() if "warning: " in out else "")
    # and the values are the running drive's: estimated speed near the true one
    est = [float(r["pdo_speed_est"]) for r in rows if r["pdo_speed_est"] != ""]
    meas = [float(r["pdo_speed_meas"]) for r in rows if r["pdo_speed_meas"] != ""]
    assert abs(sum(est) / len(est) - sum(meas) / len(meas)) < 50.0


def test_telemetry_off_is_explained(drive):
    dtctune("set", "telemetry_hz", "0", check=0)
    try:
        status, _, err = dtctune("monitor", "--once", "--start")
        assert status == 3 and "telemetry_hz = 0" in err, err
    finally:
        dtctune("set", "telemetry_hz", "100", check=0)


# ----------------------------------------------------------------------------- canopen package

def test_every_parameter_in_the_eds_reads(network):
    net, node = network
    failures = []
    n = 0
    for e in eds_entries():
        if e["access"] == "wo":
            continue
        try:
            data = node.sdo.upload(e["index"], e["sub"])
            n += 1
            fmt = FORMATS.get(e["dtype"])
            if fmt and len(data) < struct.calcsize(fmt):
                failures.append("%s: %d bytes" % (e["name"], len(data)))
        except Exception as ex:  # collect them all, report at once
            failures.append("%s (0x%04X:%d): %s" % (e["name"], e["index"], e["sub"], ex))
    assert not failures, "%d of %d reads failed:\n%s" % (len(failures), n + len(failures), "\n".join(failures))
    assert n > 100


def test_every_rw_numeric_parameter_refuses_one_step_outside(network):
    net, node = network
    problems = []
    checked = 0
    for e in eds_entries():
        fmt = FORMATS.get(e["dtype"])
        if e["access"] not in ("rw", "rww", "wo") or fmt is None:
            continue
        if e["index"] in (0x1010, 0x1011, 0x6040):  # commands (signatures, controlword), no range
            continue
        before = node.sdo.upload(e["index"], e["sub"])
        for side, limit, code in (("high", e["high"], ABORT_HIGH), ("low", e["low"], ABORT_LOW)):
            if e["dtype"] == 0x08:
                if limit is None:
                    continue
                bad = float32_next(limit, up=(side == "high"))
            else:
                lo, hi = INT_RANGE[e["dtype"]]
                if limit is None:
                    continue
                bad = limit + 1 if side == "high" else limit - 1
                if not lo <= bad <= hi:
                    continue  # the limit is the type's own: nothing lies beyond it
            checked += 1
            try:
                node.sdo.download(e["index"], e["sub"], struct.pack(fmt, bad))
                problems.append("%s = %r (%s limit %r): accepted" % (e["name"], bad, side, limit))
            except SdoAbortedError as ex:
                if ex.code != code:
                    problems.append("%s = %r: abort 0x%08X, expected 0x%08X" % (e["name"], bad, ex.code, code))
            after = node.sdo.upload(e["index"], e["sub"])
            if after != before:
                problems.append("%s changed from %s to %s" % (e["name"], before.hex(), after.hex()))
                node.sdo.download(e["index"], e["sub"], before)
    assert not problems, "\n".join(problems)
    assert checked > 50


# ----------------------------------------------------------------------------- scope

def test_scope_manual_png(drive):
    png, csv_path = OUT / "scope_manual.png", OUT / "scope_manual.csv"
    for p in (png, csv_path):
        if p.exists():
            p.unlink()
    _, out, _ = dtctune("scope", "--trigger", "manual",
                        "--channels", "tel_speed_est_rpm,tel_te_ref_Nm,tel_ia_A,tel_eps_hat",
                        "--png", str(png), "--csv", str(csv_path), check=0, timeout=180)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1024
    ia = [float(r["tel_ia_A"]) for r in rows]
    assert max(ia) - min(ia) > 1.0  # the motor is running: current alternates


def test_scope_triggers_on_reference_change(drive):
    """dtctune waits for a reference change; the change comes by RPDO here (the same trigger by
    an SDO `dtctune set` from a second process is test_two_dtctune_processes_share_the_sdo_channel).
    Controlword 0x0F with the new target velocity leaves the run state as it is."""
    png, csv_path = OUT / "scope_ref.png", OUT / "scope_ref.csv"
    _, out, _ = dtctune("get", "speed_ref_rpm", check=0)
    ref0 = value_of(out)
    result = {}

    bus = can.Bus(interface="socketcan", channel=CHANNEL)
    try:
        bus.send(can.Message(arbitration_id=0x000, is_extended_id=False, data=[0x01, NODE]))  # NMT start

        def capture():
            result["r"] = dtctune("scope", "--trigger", "ref", "--pretrigger", "0.25", "--wait", "60",
                                  "--channels", "tel_speed_ref_rpm,tel_speed_est_rpm",
                                  "--png", str(png), "--csv", str(csv_path), timeout=240)

        th = threading.Thread(target=capture)
        th.start()
        # armed = the drive confirmed the write of 1 to scope_command (0x2600:8)
        armed, last_cmd = False, None
        t_end = time.monotonic() + 60
        while not armed and time.monotonic() < t_end:
            m = bus.recv(0.5)
            if m is None:
                continue
            if m.arbitration_id == 0x600 + NODE and bytes(m.data[1:4]) == b"\x00\x26\x08" and m.data[0] & 0xE0 == 0x20:
                last_cmd = m.data[4]  # a download to scope_command: 0 stop, 1 arm, 2 trigger
            elif m.arbitration_id == 0x580 + NODE and bytes(m.data[:4]) == b"\x60\x00\x26\x08":
                armed = last_cmd == 1
        assert armed, "dtctune did not arm the scope"
        time.sleep(0.3)  # let the pre-trigger part fill
        bus.send(can.Message(arbitration_id=0x200 + NODE, is_extended_id=False,
                             data=struct.pack("<Hi", 0x000F, int(round(ref0)) + 100)))
        th.join(240)
    finally:
        bus.shutdown()
    status, out, err = result["r"]
    assert status == 0, err
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t_s"]) for r in rows]
    ref = [float(r["tel_speed_ref_rpm"]) for r in rows]
    before = [r for tt, r in zip(t, ref) if tt < 0]
    assert before and max(abs(r - ref0) for r in before) < 1.0   # flat before the trigger
    assert ref[-1] > ref0 + 5.0                                   # ramping to the new reference after it
    _, out, _ = dtctune("get", "speed_ref_rpm", check=0)
    assert value_of(out) == pytest.approx(round(ref0) + 100, abs=0.01)


def test_two_dtctune_processes_share_the_sdo_channel(drive):
    """Issue 12: the scope waiting for a reference change in one process (it polls its state
    over SDO), then uploading the capture (a segmented upload, over two thousand round trips),
    while another process sets and reads a gain and finally triggers the scope with an SDO
    `set speed_ref_rpm`, as in the README: every command succeeds and reads back what it wrote
    (before the SDO lock: "Node returned a value for 0x2600:09" and timeouts)."""
    csv_path = OUT / "scope_concurrent.csv"
    if csv_path.exists():
        csv_path.unlink()
    _, out, _ = dtctune("get", "speed_ref_rpm", check=0)
    ref0 = value_of(out)
    exe = shutil.which("dtctune", path=str(Path(sys.executable).parent)) or shutil.which("dtctune")
    base = [exe, "--channel", CHANNEL, "--node", str(NODE), "--eds", str(EDS)]
    scope = subprocess.Popen(base + ["scope", "--trigger", "ref", "--pretrigger", "0.25", "--wait", "120",
                                     "--channels", "speed_ref_rpm,speed_est_rpm,te_ref_Nm,ia_A",
                                     "--csv", str(csv_path)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    n_before, n_after = 0, 0
    try:
        def pair(k):
            value = 2400.0 + 10 * (k % 2)
            _, out, _ = dtctune("set", "rbfn_gamma_w", "%g" % value, check=0)
            assert value_of(out) == value
            _, out, _ = dtctune("get", "rbfn_gamma_w", check=0)
            assert value_of(out) == value

        while n_before < 4:          # the scope polls meanwhile
            pair(n_before)
            n_before += 1
        assert scope.poll() is None, scope.communicate()
        _, out, _ = dtctune("set", "speed_ref_rpm", "%g" % (round(ref0) + 50), check=0)
        while scope.poll() is None and n_after < 40:   # the upload runs meanwhile
            # `list` reads every parameter: some 170 SDO uploads back to back
            _, out, _ = dtctune("list", check=0)
            assert "rbfn_gamma_w" in out and "(" not in out.split("rbfn_gamma_w", 1)[1].split("\n")[0]
            n_after += 1
        s_out, s_err = scope.communicate(timeout=240)
    finally:
        if scope.poll() is None:
            scope.kill()
            scope.wait()
        dtctune("set", "rbfn_gamma_w", "2500", check=0)
    print("%d set+get pairs while the scope waited, %d full lists while it uploaded" % (n_before, n_after))
    assert scope.returncode == 0, s_err
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1024
    t = [float(r["t_s"]) for r in rows]
    ref = [float(r["tel_speed_ref_rpm"]) for r in rows]
    assert max(abs(r - ref0) for tt, r in zip(t, ref) if tt < 0) < 1.0   # flat before the trigger
    assert ref[-1] > ref0 + 5.0                                           # the step after it


# ----------------------------------------------------------------------------- defaults (last: stops the motor)

def test_restore_defaults_only_when_stopped_and_persistent(drive):
    default_k = float(next(e["default"] for e in eds_entries() if e["name"] == "rbfn_k"))
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    assert value_of(out) != default_k  # set and saved by the tests above
    status, _, err = dtctune("restore-defaults")
    assert status == 4 and "0x08000022" in err, err  # not while running
    dtctune("set", "controlword", "6", check=0)      # CiA 402 shutdown: the drive stops
    time.sleep(0.5)
    dtctune("restore-defaults", check=0)
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    assert value_of(out) == default_k
    assert drive.stop() == 0
    drive.start()
    _, out, _ = dtctune("get", "rbfn_k", check=0)
    assert value_of(out) == default_k                # the defaults were stored too
