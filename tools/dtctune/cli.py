"""dtctune: read, set, save parameters of the DTC drive over CANopen; watch and record telemetry;
capture the drive's scope.

Every failure ends with one line on stderr and a non-zero exit status (see EXIT_* in errors.py).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

from . import __version__
from .errors import DtctuneError, EXIT_NO_ANSWER, EXIT_OK, EXIT_USAGE

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
The EDS is --eds PATH, else $DTCTUNE_EDS, else build/host/drive.eds in the repository.
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
    p = _Parser(prog="dtctune", description=__doc__.split("\n\n")[0],
                epilog=EPILOG, formatter_class=_Formatter)
    p.add_argument("--interface", default="socketcan",
                   help="python-can interface (socketcan, virtual, pcan, ...; default socketcan)")
    p.add_argument("--channel", default="vcan0", help="CAN channel (default vcan0)")
    p.add_argument("--bitrate", type=int, default=None, help="bit rate for interfaces that set it")
    p.add_argument("--node", type=_node_id, default=1, help="CANopen node id of the drive, 1..127 (default 1)")
    p.add_argument("--eds", default=None, help="EDS of the drive (default build/host/drive.eds)")
    p.add_argument("--timeout", type=_positive, default=1.0, help="SDO answer timeout, s (default 1.0)")
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

    c = sub.add_parser("monitor", help="live telemetry table")
    c.add_argument("--once", action="store_true", help="print one table and exit")
    c.add_argument("--interval", type=_positive, default=0.5, help="refresh interval, s (default 0.5)")
    c.add_argument("--seconds", type=_positive, default=None, help="stop after this many seconds")
    _telemetry_options(c)

    c = sub.add_parser("record", help="record telemetry to CSV")
    c.add_argument("--seconds", type=_positive, required=True,
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
    c.add_argument("--wait", type=_positive, default=30.0, help="how long to wait for the trigger, s (default 30)")
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


def _node_id(text: str) -> int:
    try:
        v = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError("node id must be a number 1..127, got '%s'" % text)
    if not 1 <= v <= 127:
        raise argparse.ArgumentTypeError("node id must be 1..127, got %d" % v)
    return v


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("'%s' is not a number" % text)
    if not v > 0 or v != v or v == float("inf"):
        raise argparse.ArgumentTypeError("must be a positive number, got '%s'" % text)
    return v


# ---------------------------------------------------------------------------- commands

def _open(args, dic):
    from .link import Link, SdoLock, lock_path, open_transport
    transport = open_transport(args.interface, args.channel, args.bitrate)
    lock = SdoLock(lock_path(args.interface, args.channel, args.node))
    return Link(transport, dic, args.node, args.timeout, channel=args.channel, lock=lock)


def _fmt(p, raw) -> str:
    s = p.format(raw)
    return s + (" " + p.unit if p.unit else "")


def cmd_list(args, dic, out) -> int:
    params = list(dic.select(args.all, args.filter))
    if not params:
        raise DtctuneError("no parameter matches '%s'" % args.filter if args.filter else "the EDS lists no parameters")
    link = None if args.no_values else _open(args, dic)
    try:
        rows = []
        for p in params:
            if link is None or not p.readable:
                val = "" if link is None else "(write-only)"
            else:
                try:
                    val = p.format(link.read(p))
                except DtctuneError as e:
                    if e.status == EXIT_NO_ANSWER:
                        raise
                    val = "(%s)" % str(e).split(": ", 1)[-1]
            rows.append((p.name, val, p.unit, p.format_range(), p.access, p.address,
                         p.description if args.long else ""))
        head = ("name", "value", "unit", "range", "access", "object", "description" if args.long else "")
        w = [max(len(r[i]) for r in rows + [head]) for i in range(6)]
        fmt = "%%-%ds  %%%ds  %%-%ds  %%-%ds  %%-%ds  %%-%ds  %%s" % tuple(w)
        print((fmt % head).rstrip(), file=out)
        for r in rows:
            print((fmt % r).rstrip(), file=out)
    finally:
        if link:
            link.close()
    return EXIT_OK


def cmd_get(args, dic, out) -> int:
    params = [dic.lookup(n) for n in args.names]
    with _open(args, dic) as link:
        for p in params:
            raw = link.read(p)
            if args.value_only:
                print(p.format(raw), file=out)
            else:
                print("%s = %s" % (p.name, _fmt(p, raw)), file=out)
    return EXIT_OK


def cmd_set(args, dic, out) -> int:
    p = dic.lookup(args.name)
    raw = p.parse(args.value)
    if not args.no_check:
        p.check(raw)
    with _open(args, dic) as link:
        link.write(p, raw)
        if p.readable:
            print("%s = %s" % (p.name, _fmt(p, link.read(p))), file=out)
        else:
            print("%s written" % p.name, file=out)
    return EXIT_OK


def cmd_save(args, dic, out) -> int:
    with _open(args, dic) as link:
        link.save()
    print("saved: the drive's parameters are stored in non-volatile memory", file=out)
    return EXIT_OK


def cmd_restore(args, dic, out) -> int:
    with _open(args, dic) as link:
        link.restore_defaults()
    print("restored: the drive runs with its default parameters and has stored them", file=out)
    return EXIT_OK


def _telemetry_setup(args, dic, link):
    from . import telemetry
    tpdos = telemetry.read_layout(dic, None if args.from_eds else link)
    if not tpdos:
        raise DtctuneError("the drive has no enabled telemetry TPDO")
    cap = telemetry.Capture(link, tpdos, source_factory=lambda ids: telemetry.open_source(
        args.interface, args.channel, args.bitrate, ids))
    cap.start()
    if args.start:
        link.nmt("OPERATIONAL")
    return telemetry, tpdos, cap


# How long monitor/record listen for telemetry before switching the drive to NMT operational.
QUIET_BEFORE_START_S = 0.5


def _await_telemetry(args, telemetry, cap, link, tpdos, timeout_s: float, note) -> None:
    """Wait for the first telemetry; when none flows, switch the node to NMT operational
    (unless --no-start) and wait again."""
    if not args.start and not args.no_start:
        if not cap.wait_all_seen(QUIET_BEFORE_START_S) and not cap.snapshot():
            link.nmt("OPERATIONAL")
            note("no telemetry from node %d: switched it to NMT operational (TPDOs are sent only there; "
                 "--no-start prevents this)" % args.node)
    telemetry.wait_first(cap, link, tpdos, timeout_s, can_start=not args.no_start)


def cmd_monitor(args, dic, out) -> int:
    with _open(args, dic) as link:
        telemetry, tpdos, cap = _telemetry_setup(args, dic, link)
        try:
            cap.keep = False
            _await_telemetry(args, telemetry, cap, link, tpdos, max(2.0, 3 * args.interval),
                             lambda text: print(text, file=out))
            title = "node %d on %s" % (args.node, args.channel)
            if args.once:
                time.sleep(0.5)  # long enough for a first rate figure
                print(telemetry.render_table(tpdos, cap, title), file=out)
                return EXIT_OK
            # Screen codes (clear, home) only on a terminal that understands them.
            interactive = hasattr(out, "isatty") and out.isatty() and os.environ.get("TERM", "") not in ("", "dumb")
            t_end = None if args.seconds is None else time.monotonic() + args.seconds
            try:
                while t_end is None or time.monotonic() < t_end:
                    text = telemetry.render_table(tpdos, cap, title + "   (Ctrl-C to stop)")
                    if interactive:
                        out.write("\x1b[H\x1b[2J" + text + "\n")
                    else:
                        out.write(text + "\n\n")
                    out.flush()
                    time.sleep(args.interval)
            except KeyboardInterrupt:
                pass
        finally:
            cap.stop()
    return EXIT_OK


def cmd_record(args, dic, out) -> int:
    from pathlib import Path
    dest = Path(args.csv)
    if dest.parent and not dest.parent.exists():
        raise DtctuneError("cannot write %s: directory %s does not exist" % (dest, dest.parent))
    with _open(args, dic) as link:
        telemetry, tpdos, cap = _telemetry_setup(args, dic, link)
        t_until = None
        try:
            _await_telemetry(args, telemetry, cap, link, tpdos, 2.0, lambda text: print(text, file=out))
            clock = _drive_clock(dic, link)
            # The window, in the clock of the frames' receive timestamps: frames still queued
            # in the socket when it ends are read afterwards and counted where they belong.
            t_from = time.time()
            cap.window_from(t_from)
            tick0, wall0 = (int(link.read(clock[0])), time.monotonic()) if clock else (None, None)
            time.sleep(max(0.0, t_from + args.seconds - time.time()))
            t_until = time.time()
            tick1, wall1 = (int(link.read(clock[0])), time.monotonic()) if clock else (None, None)
        finally:
            cap.stop(until=t_until)
        frames = list(cap.frames)
        tmp = dest.with_name(dest.name + ".partial")
        try:
            with open(tmp, "w", newline="") as f:
                n = telemetry.write_csv(f, frames, tpdos)
            os.replace(tmp, dest)
        except OSError as e:
            try:
                tmp.unlink()
            except OSError:
                pass
            raise DtctuneError("cannot write %s: %s" % (dest, e.strerror or e)) from None
        rates = ", ".join("TPDO%d %s Hz" % (t.number, "%.1f" % cap.rate_hz(t.cob_id) if cap.rate_hz(t.cob_id) else "-")
                          for t in tpdos)
        print("recorded %d rows (%d frames) in %.1f s to %s: %s" % (n, len(frames), args.seconds, dest, rates),
              file=out)
        if cap.kernel_drops:
            print("warning: %d frames were lost in this PC's receive buffer (the PC did not keep up)"
                  % cap.kernel_drops, file=out)
        if clock:
            drive_s = ((tick1 - tick0) % (1 << 32)) * clock[1]
            print("drive clock: %.3f s in %.3f s of wall time (the drive ran at %.3fx real time)"
                  % (drive_s, wall1 - wall0, drive_s / (wall1 - wall0)), file=out)
    return EXIT_OK


def _drive_clock(dic, link):
    """(tick counter parameter, tick period in s) when the drive publishes them, else None.
    They tell the rate in the drive's own time (a simulated drive may run behind the wall clock)."""
    try:
        tick, period = dic.lookup("tel_tick"), dic.lookup("period_s")
        period_s = float(link.read(period))
    except DtctuneError:
        return None
    return (tick, period_s) if period_s > 0 else None


def cmd_scope(args, dic, out) -> int:
    from . import scope
    with _open(args, dic) as link:
        return scope.run(args, dic, link, out)


COMMANDS = {
    "list": cmd_list, "get": cmd_get, "set": cmd_set, "save": cmd_save,
    "restore-defaults": cmd_restore, "monitor": cmd_monitor, "record": cmd_record, "scope": cmd_scope,
}


def main(argv: Optional[List[str]] = None, out=None) -> int:
    out = out or sys.stdout
    try:
        args = build_parser().parse_args(argv)
        from .od import Dictionary, find_eds
        dic = Dictionary(find_eds(args.eds), args.node)
        return COMMANDS[args.command](args, dic, out)
    except DtctuneError as e:
        print("dtctune: error: %s" % e, file=sys.stderr)
        return e.status
    except KeyboardInterrupt:
        print("dtctune: interrupted", file=sys.stderr)
        return 130


def entry() -> None:
    sys.exit(main())


if __name__ == "__main__":
    entry()
