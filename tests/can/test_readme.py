"""README as a test: the "Tuning over CAN" walk-through of README.md, command for command.

The commands are taken from the first ```sh block of that section when the test runs, so the
README cannot drift from the tool: each line runs with `sh -c` in a scratch directory that
looks like the repository (links to .venv, build, host_sim), in order, with what earlier
`. FILE` lines set up, and its exit status and key output are checked:

  * `. .venv/bin/activate`: dtctune is on PATH afterwards
  * `... dtc-sim ... &`: started as printed (the test waits for its CANopen boot-up message,
    as a user sees the prompt come back); it runs until the end. Another `... &` line starts
    as printed too, and its --png must appear (see scope)
  * `dtctune list --filter X`: a table, every name contains X
  * `dtctune get NAME   # VALUE`: prints VALUE
  * `dtctune set NAME VALUE`: reads VALUE back; a line whose comment says "refused" exits with
    status 4 and the abort code of its comment (0x06090031)
  * `dtctune record --seconds S --csv OUT`: OUT has one row per telemetry cycle at the
    telemetry_hz set before, in the drive's clock (10 %), and no lost cycle
  * `dtctune scope ... --png OUT` and the set that triggers it: OUT becomes a PNG
  * `dtctune save`: after a restart of the SIL as printed (same --nvm), every value set before
    the save reads back as set
  * `dtctune set controlword 6 && dtctune restore-defaults`: the defaults (from the EDS) are back

Runs where vcan0 exists: inside User-Mode Linux via tests/can/run_python_test.sh --uml (ctest
`can.uml_readme`). Environment: DTC_CAN_OUT (where the scratch directory is kept).
"""
from __future__ import annotations

import csv
import os
import re
import shlex
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
CHANNEL = "vcan0"
NODE = 1


def readme_commands():
    """[(command, comment)] of the first ```sh block under '## Tuning over CAN'."""
    text = README.read_text(encoding="utf-8")
    m = re.search(r"^## Tuning over CAN\n(.*?)(?=^## )", text, re.S | re.M)
    assert m, "README.md has no '## Tuning over CAN' section"
    block = re.search(r"^```sh\n(.*?)^```", m.group(1), re.S | re.M)
    assert block, "the 'Tuning over CAN' section has no ```sh block"
    out = []
    for line in block.group(1).splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        m = re.match(r"^(.*?)(?:\s+#\s?(.*))?$", line)
        out.append((m.group(1).strip(), (m.group(2) or "").strip()))
    return out


def test_readme_block_is_found_and_complete():
    """The extraction itself: the walk-through's commands are all there (a README that loses
    one of the checked steps fails here instead of passing with less)."""
    cmds = [c for c, _ in readme_commands()]
    words = " ".join(cmds)
    for needed in ("dtc-sim run", "dtctune list", "dtctune get", "--no-check", "telemetry_hz",
                   "dtctune record", "dtctune scope", "dtctune save", "restore-defaults"):
        assert needed in words, "README walk-through lost its '%s' step" % needed


# ----------------------------------------------------------------------------- running it

def _out_dir() -> Path:
    d = os.environ.get("DTC_CAN_OUT")
    base = Path(d) if d else Path(tempfile.mkdtemp(prefix="dtc-readme-"))
    work = base / "readme"
    if work.exists():
        for p in work.iterdir():
            if p.is_symlink() or p.is_file():
                p.unlink()
    work.mkdir(parents=True, exist_ok=True)
    for name in (".venv", "build", "host_sim", "tools"):
        os.symlink(REPO / name, work / name)
    return work


def _value(text: str) -> float:
    m = re.search(r"^\s*\S+ = (\S+)", text, re.M)
    assert m, "no 'name = value' in: %r" % text
    return float(m.group(1))


class Session:
    """The README's lines run one by one, like a user typing them into one shell."""

    def __init__(self, work: Path):
        self.work = work
        self.prefix = []          # `. FILE` lines: set up the environment of later lines
        self.bg = []              # (command, Popen) of `&` lines
        self.n = 0

    def run(self, cmd: str, timeout: float = 180):
        """(status, stdout, stderr) of one line. Output goes to files, not pipes: a process the
        line leaves behind (scope --background) must not keep us waiting for end-of-file."""
        self.n += 1
        base = self.work / ("cmd%02d" % self.n)
        script = "; ".join(self.prefix + [cmd])
        with open(str(base) + ".out", "w") as o, open(str(base) + ".err", "w") as e:
            r = subprocess.run(["sh", "-c", script], cwd=self.work, stdout=o, stderr=e, timeout=timeout)
        out = Path(str(base) + ".out").read_text()
        err = Path(str(base) + ".err").read_text()
        print("$ %s\n-> %d\n%s%s" % (cmd, r.returncode, out, err))
        return r.returncode, out, err

    def start(self, cmd: str):
        assert cmd.endswith("&")
        body = cmd[:-1].strip()
        log = open(self.work / ("background-%d.log" % len(self.bg)), "ab")
        p = subprocess.Popen(["sh", "-c", "; ".join(self.prefix + ["exec " + body])], cwd=self.work,
                             stdout=log, stderr=subprocess.STDOUT)
        self.bg.append((body, p, log))
        return p

    def stop_background(self, only_sim=False):
        rcs = []
        keep = []
        for body, p, log in self.bg:
            if only_sim and "dtc-sim" not in body:
                keep.append((body, p, log))
                continue
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
                try:
                    p.wait(20)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
            rcs.append(p.returncode)
            log.close()
        self.bg = keep
        return rcs


def start_and_wait_boot(start, timeout_s=30.0):
    """start() the SIL and wait for the CANopen boot-up message of our node (0x700 + id, data 00)."""
    import can
    bus = can.Bus(interface="socketcan", channel=CHANNEL,
                  can_filters=[{"can_id": 0x700 + NODE, "can_mask": 0x7FF}])
    try:
        proc = start()
        t_end = time.monotonic() + timeout_s
        while time.monotonic() < t_end:
            m = bus.recv(0.1)
            if m is not None and bytes(m.data[:1]) == b"\x00":
                return
            assert proc.poll() is None, "dtc-sim exited with status %s" % proc.returncode
        raise AssertionError("no boot-up message from node %d within %.0f s" % (NODE, timeout_s))
    finally:
        bus.shutdown()


def eds_default(name: str) -> float:
    import configparser
    eds = configparser.RawConfigParser(inline_comment_prefixes=(";",))
    eds.optionxform = str
    eds.read(str(REPO / "build" / "host" / "drive.eds"))
    for sec in eds.sections():
        if eds.get(sec, "ParameterName", fallback=None) == name:
            return float(eds.get(sec, "DefaultValue"))
    raise AssertionError("%s not in the EDS" % name)


def wait_png(path: Path, timeout_s: float) -> None:
    t_end = time.monotonic() + timeout_s
    while time.monotonic() < t_end:
        if path.exists() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n":
            return
        time.sleep(0.2)
    raise AssertionError("%s was not written within %.0f s" % (path, timeout_s))


def test_readme_walkthrough():
    work = _out_dir()
    s = Session(work)
    sim_cmd = None
    values = {}            # what the walk-through set, name -> value (read back)
    saved = None           # values at the save
    pending_png = []       # scope outputs still to come
    telemetry_hz = None
    try:
        for cmd, comment in readme_commands():
            argv = shlex.split(cmd.rstrip("&").strip()) if "&&" not in cmd else []
            if cmd.startswith(". "):
                s.prefix.append(cmd)
                status, out, _ = s.run("command -v dtctune")
                assert status == 0 and os.path.realpath(out.strip()) == os.path.realpath(
                    REPO / ".venv" / "bin" / "dtctune"), \
                    "after '%s' dtctune is not the venv's: %r" % (cmd, out)
                continue
            if cmd.endswith("&"):
                if "dtc-sim" in cmd:
                    sim_cmd = cmd
                    start_and_wait_boot(lambda: s.start(cmd))
                else:  # started as printed; what it writes is checked where it is needed
                    s.start(cmd)
                    if "--png" in argv:
                        pending_png.append(work / argv[argv.index("--png") + 1])
                continue
            status, out, err = s.run(cmd)
            if "refused" in comment:
                code = re.search(r"0x[0-9A-Fa-f]{8}", comment).group(0)
                assert status == 4, "'%s' should be refused by the drive (status 4), got %d: %s" % (cmd, status, err)
                assert code.lower() in err.lower(), "'%s': abort code %s not in %r" % (cmd, code, err)
                assert len(err.strip().splitlines()) == 1
                continue
            assert status == 0, "'%s' -> status %d\n%s%s" % (cmd, status, out, err)
            tool, verb = (argv[0], argv[1]) if len(argv) >= 2 else (None, None)
            if "&&" in cmd:
                # dtctune state disable && dtctune restore-defaults
                assert "restore-defaults" in cmd and "restored" in out
                for name in values:
                    if name in ("controlword", "speed_ref_rpm"):  # commands, not stored parameters
                        continue
                    st, o, e = s.run("dtctune get %s" % name)
                    assert st == 0 and _value(o) == pytest.approx(eds_default(name)), \
                        "%s not back to its default %s after restore-defaults: %s" % (name, eds_default(name), o)
                continue
            assert tool == "dtctune", cmd
            if verb == "list":
                lines = out.splitlines()
                assert lines[0].split()[:6] == ["name", "value", "unit", "range", "access", "object"]
                filt = argv[argv.index("--filter") + 1] if "--filter" in argv else ""
                names = [l.split()[0] for l in lines[1:]]
                assert names and all(filt in n for n in names), out
            elif verb == "get":
                if comment:
                    assert _value(out) == float(comment.split()[0]), "'%s' printed %r, README says %s" % (
                        cmd, out, comment)
            elif verb == "set":
                name, value = [a for a in argv[2:] if not a.startswith("--")]
                assert _value(out) == pytest.approx(float(value)), out
                values[name] = float(value)
                if name == "telemetry_hz":
                    telemetry_hz = float(value)
            elif verb == "record":
                check_record(work / argv[argv.index("--csv") + 1], float(argv[argv.index("--seconds") + 1]),
                             telemetry_hz, out, telemetry_rate_in_drive_clock(s))
            elif verb == "scope":
                assert "armed" in out, out
                pending_png.append(work / argv[argv.index("--png") + 1])
            elif verb == "state":
                assert out.strip() == comment.split(": ", 1)[1].strip(), \
                    "'%s' printed %r, README says %s" % (cmd, out, comment)
            elif verb == "save":
                assert "saved" in out
                saved = dict(values)
                # the scope armed above finishes in the background: its PNG, before the restart
                for png in pending_png:
                    wait_png(png, 90)
                pending_png = []
                # "survives a restart with the same --nvm": stop the SIL, start it as printed
                assert s.stop_background(only_sim=True) == [0], "dtc-sim did not stop cleanly"
                start_and_wait_boot(lambda: s.start(sim_cmd))
                for name, v in saved.items():
                    if name in ("speed_ref_rpm",):  # a set point of the running motor, not stored
                        continue
                    st, o, e = s.run("dtctune get %s" % name)
                    assert st == 0 and _value(o) == pytest.approx(v), \
                        "%s = %s was saved, after the restart: %s%s" % (name, v, o, e)
            else:
                raise AssertionError("the README has a command this test does not check: %s" % cmd)
        assert saved is not None, "the walk-through has no save"
        for png in pending_png:
            wait_png(png, 120)
    finally:
        rcs = s.stop_background()
    assert all(rc == 0 for rc in rcs), "dtc-sim ended with %s" % rcs


def _tick_seq(s: Session):
    """(drive tick, telemetry cycle counter) at one instant of the drive's clock: the counter
    read between two reads of the tick, stamped with their mean."""
    st, out, err = s.run("dtctune get tel_tick pdo_seq tel_tick --value-only")
    assert st == 0, err
    t1, seq, t2 = (int(float(v)) for v in out.split())
    return (t1 + ((t2 - t1) % (1 << 32)) / 2.0, seq)


def telemetry_rate_in_drive_clock(s: Session, min_ticks: float = 10000) -> float:
    """The telemetry rate in the drive's own clock from SDO reads of its tick counter and its
    cycle counter (pdo_seq) over at least min_ticks ticks (2 s): both values are the drive's,
    so how fast the SIL runs beside other work does not enter."""
    period_s = eds_default("period_s")
    tick0, seq0 = _tick_seq(s)
    while True:
        tick1, seq1 = _tick_seq(s)
        if (tick1 - tick0) % (1 << 32) >= min_ticks:
            break
        time.sleep(0.5)
    return ((seq1 - seq0) % 65536) / (((tick1 - tick0) % (1 << 32)) * period_s)


def check_record(path: Path, seconds: float, rate_hz, out: str, drive_rate_hz: float) -> None:
    """The CSV holds `seconds` of telemetry from its first row on (receive timestamps), one row
    per cycle with none lost, and dtctune's drive-clock figure agrees with the rate measured
    independently in the drive's clock (drive_rate_hz, SDO reads of its tick and cycle counters)."""
    assert rate_hz, "the README records before setting telemetry_hz"
    assert drive_rate_hz == pytest.approx(rate_hz, rel=0.02), \
        "the drive sends %.1f telemetry cycles per second of its clock, %s set" % (drive_rate_hz, rate_hz)
    with open(path) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) > 10, out
    t = [float(r["t_s"]) for r in rows]
    span = t[-1] - t[0]
    rate = (len(rows) - 1) / span
    m = re.search(r"drive clock: ([\d.]+) s in ([\d.]+) s of wall time \(the drive ran at ([\d.]+)x", out)
    assert m, out
    drive_s, wall_s, realtime = float(m.group(1)), float(m.group(2)), float(m.group(3))
    print("record: %d rows over %.3f s, %.1f Hz wall clock, drive clock %.3f s (SIL at %.2fx real time), "
          "telemetry %.1f Hz in the drive's clock" % (len(rows), span, rate, drive_s, realtime, drive_rate_hz))
    # "5 s asked, 5 s recorded": the rows span the window up to its last cycle. What may miss at
    # its end is one pause of the SIL (it runs beside other work): as long as the longest one
    # between the rows, at least 0.5 s.
    pause = max(0.5, max(b - a for a, b in zip(t, t[1:])))
    assert seconds - pause - 2.0 / rate_hz <= span < seconds, "rows over %.3f s for %.1f s asked" % (span, seconds)
    # dtctune's drive clock spans the same rows: their cycles at the independently measured rate
    assert wall_s == pytest.approx(span, abs=1e-3), out
    assert drive_s == pytest.approx((len(rows) - 1) / drive_rate_hz, rel=0.03), out
    seq = [int(r["pdo_seq"]) for r in rows if r["pdo_seq"] != ""]
    gaps = sum(((b - a) % 65536) - 1 for a, b in zip(seq, seq[1:]))
    assert gaps == 0, "%d telemetry cycles lost" % gaps
