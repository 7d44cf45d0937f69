"""dtctune's command line against a fake drive on python-can's virtual bus."""
import csv

import pytest

from dtctune.cli import main
from dtctune.errors import EXIT_NO_ANSWER, EXIT_REFUSED, EXIT_USAGE

from conftest import EDS

TOOLS = EDS.resolve().parents[3]  # tools/ (the package root), for runs without site (-S)


def one_error_line(err: str) -> str:
    lines = [l for l in err.splitlines() if l.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert lines[0].startswith("dtctune: error: ")
    return lines[0]


# ------------------------------------------------------------------ arguments and EDS

def test_no_command_is_one_line_usage_error(run):
    status, out, err = run()
    assert status == EXIT_USAGE
    assert "required" in one_error_line(err)


@pytest.mark.parametrize("node", ["0", "128", "x"])
def test_bad_node_id(run, node):
    status, _, err = run("--node", node, "get", "speed.ref_rpm")
    assert status == EXIT_USAGE
    assert "node id" in one_error_line(err)


def test_help_exits_zero(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--help"])
    assert e.value.code == 0
    assert "restore-defaults" in capsys.readouterr().out


def test_missing_eds(run, tmp_path):
    status, _, err = run("get", "speed.ref_rpm", eds=tmp_path / "nope.eds")
    assert status == EXIT_USAGE
    assert "EDS file not found" in one_error_line(err)


def test_malformed_eds(run, tmp_path):
    bad = tmp_path / "bad.eds"
    bad.write_text("[2000]\nParameterName=x\nObjectType=0x7\nDataType=zz\n")
    status, _, err = run("list", "--no-values", eds=bad)
    assert status == EXIT_USAGE
    assert "cannot read EDS" in one_error_line(err)


def test_eds_from_environment(run, monkeypatch):
    monkeypatch.setenv("DTCTUNE_EDS", str(EDS))
    status, out, _ = run("list", "--no-values", eds=None)
    assert status == 0
    assert "speed.ref_rpm" in out


def test_list_without_drive_shows_units_ranges_access(run):
    status, out, _ = run("list", "--no-values")
    assert status == 0
    line = next(l for l in out.splitlines() if l.startswith("speed.ref_rpm"))
    assert "rpm" in line and "-3000.0..3000.0" in line and "rw" in line and "0x2000:0" in line
    assert "rbfn.gamma_w" in out and "tel.tick" in out
    assert "Device type" not in out  # communication area only with --all


def test_unknown_name_suggests(run, drive):
    status, _, err = run("get", "speed.ref_rmp")
    assert status == EXIT_USAGE
    line = one_error_line(err)
    assert "unknown parameter 'speed.ref_rmp'" in line and "speed.ref_rpm" in line


# ------------------------------------------------------------------ SDO access

def test_get_and_address_forms(run, drive):
    status, out, _ = run("get", "speed.ref_rpm", "0x2100:1", "0x2100sub2")
    assert status == 0
    assert out.splitlines() == ["speed.ref_rpm = 0.0 rpm", "rbfn.gamma_w = 50.0 1/s", "rbfn.n_hidden = 5"]


def test_list_with_values(run, drive):
    status, out, _ = run("list")
    assert status == 0
    line = next(l for l in out.splitlines() if l.startswith("speed.ip.kp"))
    assert "0.5" in line and "ro" in line


def test_set_in_range_reads_back(run, drive):
    status, out, _ = run("set", "rbfn.gamma_w", "125.5")
    assert status == 0, out
    assert out.strip() == "rbfn.gamma_w = 125.5 1/s"
    assert drive.value(0x2100, 1) == pytest.approx(125.5)


def test_set_hex_integer(run, drive):
    status, out, _ = run("set", "rbfn.n_hidden", "0x7")
    assert status == 0
    assert drive.value(0x2100, 2) == 7


@pytest.mark.parametrize("value,words", [("3000.5", "outside the range"), ("-4000", "outside the range")])
def test_set_out_of_range_is_not_sent(run, drive, value, words):
    status, _, err = run("set", "speed.ref_rpm", value)
    assert status == EXIT_USAGE
    assert words in one_error_line(err)
    assert drive.writes == []


@pytest.mark.parametrize("value,code,words", [
    ("3000.5", "0x06090031", "value too high"),
    ("-3000.5", "0x06090032", "value too low"),
])
def test_drive_refusal_shown_in_words(run, drive, value, code, words):
    status, _, err = run("set", "--no-check", "speed.ref_rpm", value)
    assert status == EXIT_REFUSED
    line = one_error_line(err)
    assert words in line and code in line
    assert drive.value(0x2000) == 0.0  # unchanged


def test_read_only_refused_locally_and_by_drive(run, drive):
    status, _, err = run("set", "speed.ip.kp", "1")
    assert status == EXIT_USAGE and "read-only" in one_error_line(err)
    status, _, err = run("set", "--no-check", "speed.ip.kp", "1")
    assert status == EXIT_REFUSED
    assert "read-only (0x06010002)" in one_error_line(err)


@pytest.mark.parametrize("value", ["abc", "nan", "inf", "1.5"])
def test_set_not_a_valid_number(run, drive, value):
    status, _, err = run("set", "rbfn.n_hidden", value)
    assert status == EXIT_USAGE
    one_error_line(err)
    assert drive.writes == []


def test_timeout_without_drive(run):
    status, _, err = run("get", "speed.ref_rpm")  # nobody on this channel
    assert status == EXIT_NO_ANSWER
    line = one_error_line(err)
    assert "timeout" in line and "node 1" in line


def test_save_and_restore_send_signatures(run, drive):
    assert run("save")[0] == 0
    assert run("restore-defaults")[0] == 0
    assert drive.stored == [(0x1010, 0x65766173), (0x1011, 0x64616F6C)]


def test_unknown_interface_is_one_line(run):
    status, _, err = run("--interface", "no-such-interface", "get", "speed.ref_rpm")
    assert status == EXIT_NO_ANSWER
    assert "cannot open CAN interface" in one_error_line(err)


# ------------------------------------------------------------------ telemetry

def test_monitor_once_without_telemetry_says_why(run, drive):
    status, _, err = run("monitor", "--once", "--from-eds")
    assert status == EXIT_NO_ANSWER
    assert "NMT operational" in one_error_line(err)


def test_monitor_once_table(run, drive):
    th, stop = drive.send_tpdos(200, 3.0)
    try:
        status, out, _ = run("monitor", "--once", "--from-eds")
    finally:
        stop.set()
        th.join()
    assert status == 0
    line = next(l for l in out.splitlines() if l.startswith("tel.vc_diff_dV"))
    assert "-3.7" in line and " V " in line  # -37 * factor 0.1
    assert "tel.te_ref_Nm" in out and "-2.5" in out


def test_record_csv_rows_and_rate(run, drive, tmp_path):
    out_csv = tmp_path / "rec.csv"
    th, stop = drive.send_tpdos(200, 4.0, start_tick=1000)
    try:
        status, out, err = run("record", "--seconds", "1.0", "--csv", str(out_csv), "--from-eds")
    finally:
        stop.set()
        th.join()
    assert status == 0, err
    with open(out_csv) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["t_s", "tel.speed_est_rpm", "tel.te_ref_Nm", "tel.vc_diff_dV", "tel.tick"]
    # one row per telemetry period, each with both TPDOs, ticks consecutive
    ticks = [int(r["tel.tick"]) for r in rows]
    assert ticks == list(range(ticks[0], ticks[0] + len(ticks)))
    assert float(rows[0]["tel.vc_diff_dV"]) == pytest.approx(-3.7)
    span = float(rows[-1]["t_s"]) - float(rows[0]["t_s"])
    rate = (len(rows) - 1) / span
    assert rate == pytest.approx(200, rel=0.15)
    assert "TPDO1" in out and "TPDO2" in out


def test_timeout_in_a_real_process_prints_exactly_one_line(tmp_path):
    """As a user runs it: a separate process, logging of the libraries included."""
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-m", "dtctune", "--interface", "virtual", "--channel", "nobody-here",
                        "--timeout", "0.2", "--eds", str(EDS), "get", "speed.ref_rpm"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == EXIT_NO_ANSWER
    assert r.stdout == ""
    line = one_error_line(r.stderr)
    assert "timeout" in line


# ------------------------------------------------------------------ issue 12: as printed in README

def test_record_without_start_switches_drive_operational(run, drive, tmp_path):
    """`dtctune record --seconds S --csv OUT` (no --start): the fake drive sends telemetry only
    after an NMT start, as the real one; record sends it and records from then on."""
    out_csv = tmp_path / "rec.csv"
    started = []

    def on_nmt(cmd):
        if cmd == 0x01 and not started:
            started.append(drive.send_tpdos(200, 3.0))

    drive.on_nmt = on_nmt
    try:
        status, out, err = run("record", "--seconds", "1.0", "--csv", str(out_csv), "--from-eds")
    finally:
        for th, stop in started:
            stop.set()
            th.join()
    assert status == 0, err
    assert drive.nmt == [0x01]
    assert "switched it to NMT operational" in out
    with open(out_csv) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) > 100


def test_record_no_start_does_not_start(run, drive, tmp_path):
    status, _, err = run("record", "--no-start", "--seconds", "0.5", "--csv", str(tmp_path / "r.csv"),
                         "--from-eds")
    assert status == EXIT_NO_ANSWER
    assert "--no-start" in one_error_line(err)
    assert drive.nmt == []
    assert not (tmp_path / "r.csv").exists()


def test_record_does_not_start_when_telemetry_flows(run, drive, tmp_path):
    th, stop = drive.send_tpdos(200, 3.0)
    try:
        status, out, err = run("record", "--seconds", "0.5", "--csv", str(tmp_path / "r.csv"), "--from-eds")
    finally:
        stop.set()
        th.join()
    assert status == 0, err
    assert drive.nmt == [] and "switched" not in out


class _Tty:
    """A stand-in for a terminal: collects text, says it is a tty."""

    def __init__(self):
        self.parts = []

    def write(self, s):
        self.parts.append(s)

    def flush(self):
        pass

    def isatty(self):
        return True


@pytest.mark.parametrize("tty", [False, True])
def test_monitor_screen_codes_only_on_a_terminal(channel, drive, capsys, monkeypatch, tty):
    monkeypatch.setenv("TERM", "xterm")
    out = _Tty() if tty else None
    th, stop = drive.send_tpdos(200, 3.0)
    try:
        status = main(["--interface", "virtual", "--channel", channel, "--eds", str(EDS), "--timeout", "0.3",
                       "monitor", "--seconds", "0.8", "--interval", "0.2", "--from-eds"], out=out)
    finally:
        stop.set()
        th.join()
    assert status == 0
    text = "".join(out.parts) if tty else capsys.readouterr().out
    assert text.count("tel.vc_diff_dV") >= 2  # refreshed several times
    if tty:
        assert "\x1b[2J" in text
    else:
        assert "\x1b" not in text


def test_monitor_piped_in_a_real_process_has_no_screen_codes(tmp_path):
    """As `dtctune monitor > file` runs: stdout a file, not a terminal."""
    import subprocess
    import sys
    dest = tmp_path / "mon.txt"
    with open(dest, "w") as f:
        r = subprocess.run([sys.executable, "-m", "dtctune", "--interface", "virtual", "--channel", "nobody",
                            "--timeout", "0.2", "--eds", str(EDS), "monitor", "--no-start", "--from-eds",
                            "--seconds", "0.5"], stdout=f, stderr=subprocess.PIPE, text=True, timeout=60,
                           env=dict(__import__("os").environ, TERM="xterm"))
    assert "\x1b" not in dest.read_text() and "\x1b" not in r.stderr


def modules_loaded(argv, mods):
    """Which of mods a dtctune command (in a new interpreter without site, -S, as the launcher
    runs it) has imported when it ends: a list of booleans."""
    import subprocess
    import sys
    code = ("import sys\nsys.path[:0] = %r\nfrom dtctune.cli import main\n"
            "try:\n    main(sys.argv[1:])\nexcept SystemExit:\n    pass\n"
            "print(*[m in sys.modules for m in %r], file=sys.stderr)\n" % ([str(TOOLS)], mods))
    r = subprocess.run([sys.executable, "-S", "-c", code, "--eds", str(EDS)] + argv, capture_output=True,
                       text=True, timeout=60)
    assert "Traceback" not in r.stderr, r.stderr
    return r.stderr.split()[-len(mods):]


@pytest.mark.parametrize("argv", [["--help"], ["list", "--no-values"], ["--timeout", "0.2", "get", "speed.ref_rpm"],
                                  ["--timeout", "0.2", "set", "speed.ref_rpm", "1"]])
def test_start_up_imports_no_can_library(argv):
    """Start-up (issue 12): --help, list, get and set on socketcan import neither python-can nor
    canopen nor numpy/matplotlib (on this machine without kernel CAN, get/set end at the socket),
    nor pathlib, shutil or difflib (0.05-0.1 s each inside User-Mode Linux; tools/dtctune_bench.py
    startup)."""
    mods = ('can', 'canopen', 'numpy', 'matplotlib', 'pathlib', 'shutil', 'difflib')
    assert modules_loaded(argv, mods) == ["False"] * len(mods)


@pytest.mark.parametrize("argv", [["list", "--no-values"], ["--timeout", "0.2", "get", "speed.ref_rpm"],
                                  ["--node", "1", "set", "speed.ref_rpm", "1"], ["save"], ["restore-defaults"]])
def test_short_commands_import_no_argparse_re_or_socket_py(argv):
    """The short commands read their line without argparse (quick_args) and open the CAN socket
    through _socket: argparse, re, gettext, locale, enum and socket.py stay out of the process
    (together about 0.2 s of each command's start-up inside User-Mode Linux)."""
    mods = ('argparse', 're', 'gettext', 'locale', 'enum', 'socket', 'selectors')
    assert modules_loaded(argv, mods) == ["False"] * len(mods)
