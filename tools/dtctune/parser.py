"""dtctune's command line in full (argparse): the grammar, --help and the usage errors.

Only `--help`, usage errors and commands quick_args.py does not take need it: argparse imports
re and gettext, 0.1 s of a command's start-up inside User-Mode Linux.
"""
from __future__ import annotations

import argparse
import os
import sys

from . import __version__, cia402, quick_args
from .errors import DtctuneError, EXIT_USAGE

DESCRIPTION = ("dtctune: read, set, save parameters of the DTC drive over CANopen; watch and record "
               "telemetry;\ncapture the drive's scope.")

EPILOG = """\
commands:
  list                      names, values, units, ranges and access of the parameters
  get NAME...               read parameters (NAME, or an address like 0x2001:3)
  set NAME VALUE            write one parameter (range checked before sending), then read it back
  save                      store the present parameters in the drive's non-volatile memory (0x1010)
  restore-defaults          apply the default parameters and store them (0x1011; the drive must be stopped)
  monitor [--once]          live table of the telemetry TPDOs (plain text when not on a terminal)
  record --seconds S --csv OUT    record the telemetry TPDOs with timestamps, from now for S seconds
  scope --trigger ref|fault|manual --channels a,b,c,d --png OUT   capture the drive's scope
            (--background: return once armed, finish in a background process)

monitor and record switch the drive to NMT operational when no telemetry flows (TPDOs are sent
only there); --no-start prevents that, --start does it at once.
Two dtctune processes on one bus and node take turns on the drive's single SDO channel (an
flock on $DTCTUNE_LOCK_DIR/dtctune-sdo-INTERFACE-CHANNEL-nodeN.lock, default $TMPDIR or /tmp).

exit status: 0 ok, 2 bad arguments / unknown name / value refused before sending / EDS problem,
3 no answer (timeout) or CAN interface unusable, 4 the drive refused (SDO abort, shown in words).
The EDS is --eds PATH, else $DTCTUNE_EDS, else build/host/drive.eds in the repository, else the
EDS packaged with dtctune; the drive's dictionary signature (0x2510:8) must be the EDS's.
"""


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """argparse's formatter with the terminal width from os (argparse asks shutil, whose import
    brings bz2 and lzma: ~50 ms of every command's start-up inside User-Mode Linux, though the
    width is needed only to print help)."""

    def __init__(self, prog, indent_increment=2, max_help_position=24, width=None):
        if width is None:
            try:
                width = int(os.environ.get("COLUMNS", "0")) or os.get_terminal_size(sys.__stdout__.fileno()).columns
            except (AttributeError, ValueError, OSError):
                width = 80
            width -= 2
        super().__init__(prog, indent_increment, max_help_position, width)


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error as one line (and formats with _Formatter)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message):  # noqa: D401 - argparse API
        raise DtctuneError("%s (see %s --help)" % (message, self.prog), EXIT_USAGE)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="dtctune", description=DESCRIPTION,
                epilog=EPILOG, formatter_class=_Formatter)
    p.add_argument("--interface", default="socketcan",
                   help="python-can interface (socketcan, virtual, pcan, ...; default socketcan)")
    p.add_argument("--channel", default="vcan0", help="CAN channel (default vcan0)")
    p.add_argument("--bitrate", type=int, default=None, help="bit rate for interfaces that set it")
    p.add_argument("--node", type=node_id, default=1, help="CANopen node id of the drive, 1..127 (default 1)")
    p.add_argument("--eds", default=None, help="EDS of the drive (default: build/host/drive.eds, else the packaged one)")
    p.add_argument("--timeout", type=positive, default=1.0, help="SDO answer timeout, s (default 1.0)")
    p.add_argument("--version", action="version", version="dtctune " + __version__)
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    c = sub.add_parser("list", help="parameters with values, units, ranges")
    c.add_argument("--all", action="store_true", help="include the communication objects (0x1000-0x1FFF)")
    c.add_argument("--filter", default=None, metavar="TEXT", help="only names containing TEXT")
    c.add_argument("--no-values", action="store_true", help="from the EDS only, without asking the drive")
    c.add_argument("--long", action="store_true", help="add each parameter's description")

    c = sub.add_parser("get", help="read parameters")
    c.add_argument("names", nargs="+", metavar="NAME")
    c.add_argument("--value-only", action="store_true", help="print just the value(s)")

    c = sub.add_parser("set", help="write a parameter")
    c.add_argument("name", metavar="NAME")
    c.add_argument("value", metavar="VALUE")
    c.add_argument("--no-check", action="store_true",
                   help="send without checking range and access first (the drive then decides)")

    sub.add_parser("save", help="store parameters in non-volatile memory")
    sub.add_parser("restore-defaults", help="apply and store the default parameters")

    c = sub.add_parser("state", help="the CiA 402 state; with a target, walk the drive there")
    c.add_argument("target", nargs="?", default=None, metavar="TARGET",
                   choices=list(cia402.TARGETS),
                   help="enable (operation enabled: the motor runs), switch-on, shutdown (ready to switch "
                        "on), disable (switch on disabled: gates off), quick-stop, fault-reset; the long "
                        "names of the states are accepted too")
    c.add_argument("--wait", type=positive, default=5.0,
                   help="how long each transition may take, s (default 5)")

    c = sub.add_parser("monitor", help="live telemetry table")
    c.add_argument("--once", action="store_true", help="print one table and exit")
    c.add_argument("--interval", type=positive, default=0.5, help="refresh interval, s (default 0.5)")
    c.add_argument("--seconds", type=positive, default=None, help="stop after this many seconds")
    _telemetry_options(c)

    c = sub.add_parser("record", help="record telemetry to CSV")
    c.add_argument("--seconds", type=positive, required=True,
                   help="duration, s: the recording starts as soon as telemetry flows")
    c.add_argument("--csv", required=True, metavar="OUT", help="CSV file to write")
    _telemetry_options(c)

    c = sub.add_parser("scope", help="capture the drive's scope")
    c.add_argument("--trigger", choices=["ref", "fault", "manual"], default="manual")
    c.add_argument("--channels", required=True, metavar="a,b,c,d",
                   help="up to 4 telemetry signals: tel_speed_est_rpm, speed_est_rpm, the pdo_* name "
                        "`monitor`/`record` show (pdo_speed_est), or the 0x3000 subindex (2)")
    c.add_argument("--png", metavar="OUT", default=None, help="plot to this PNG")
    c.add_argument("--csv", metavar="OUT", default=None, help="also write the samples as CSV")
    c.add_argument("--pretrigger", type=float, default=None, metavar="FRACTION",
                   help="fraction of the record before the trigger, 0..1 (default: the drive's setting)")
    c.add_argument("--decimation", type=int, default=None, metavar="N",
                   help="keep every N-th control tick (default: the drive's setting)")
    c.add_argument("--wait", type=positive, default=30.0, help="how long to wait for the trigger, s (default 30)")
    c.add_argument("--background", action="store_true",
                   help="return as soon as the scope is armed (status 0); a background process waits for "
                        "the trigger and writes the outputs (so a script can trigger it next)")
    return p


def _telemetry_options(c: argparse.ArgumentParser) -> None:
    g = c.add_mutually_exclusive_group()
    g.add_argument("--start", action="store_true",
                   help="switch the drive to NMT operational at once (TPDOs flow only there)")
    g.add_argument("--no-start", action="store_true",
                   help="never switch the drive to NMT operational (default: only when no telemetry flows)")
    c.add_argument("--from-eds", action="store_true",
                   help="take the TPDO layout from the EDS instead of reading it from the drive")


def node_id(text: str) -> int:
    """A CANopen node id 1..127 (any int() notation); argparse.ArgumentTypeError otherwise."""
    try:
        return quick_args.node_id(text)
    except quick_args.ArgError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def positive(text: str) -> float:
    """A finite number > 0; argparse.ArgumentTypeError otherwise."""
    try:
        return quick_args.positive(text)
    except quick_args.ArgError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
