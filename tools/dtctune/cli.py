"""dtctune: read, set, save parameters of the DTC drive over CANopen; watch and record telemetry;
capture the drive's scope.

Every failure ends with one line on stderr and a non-zero exit status (see EXIT_* in errors.py).
"""
from __future__ import annotations

import os
import sys
import time

from . import quick_args
from .errors import DtctuneError, EXIT_NO_ANSWER, EXIT_OK, EXIT_USAGE

# ---------------------------------------------------------------------------- commands

def _open(args, dic):
    from .link import Link, SdoLock, lock_path, open_transport
    transport = open_transport(args.interface, args.channel, args.bitrate)
    lock = SdoLock(lock_path(args.interface, args.channel, args.node))
    link = Link(transport, dic, args.node, args.timeout, channel=args.channel, lock=lock)
    try:
        _check_signature(args, dic, link)
    except BaseException:
        link.close()
        raise
    return link


SIGNATURE = "dictionary_signature"  # 0x2510:8, computed by tools/params/gen_params.py


def _check_signature(args, dic, link) -> None:
    """The EDS must be the drive's: its dictionary signature (the CRC of every entry, the same
    in the EDS and in the firmware built from one table) against the drive's. An EDS without
    the entry (written by hand, an older table) is taken as given."""
    try:
        p = dic.lookup(SIGNATURE)
    except DtctuneError:
        return
    try:
        theirs = int(link.read(p))
    except DtctuneError as e:
        if e.status == EXIT_NO_ANSWER:
            raise
        if args.eds:
            return  # a drive without the entry, and an EDS the user chose: as given
        raise DtctuneError("the drive has no dictionary signature (%s, 0x2510:8): an older firmware; pass the "
                           "drive.eds of its build with --eds" % SIGNATURE, EXIT_USAGE) from None
    if theirs != p.var.default:
        raise DtctuneError("the EDS %s is not this drive's (dictionary signature 0x%08X, the drive's 0x%08X): "
                           "pass the drive.eds of the firmware on the drive with --eds" % (
                               dic.path, p.var.default, theirs), EXIT_USAGE)


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


def cmd_state(args, dic, out) -> int:
    """The CiA 402 state (statusword 0x6041); with a target, the controlwords (0x6040) that walk
    the drive there, one transition at a time, each confirmed by the statusword."""
    from . import cia402
    sw, cw = dic.lookup("statusword"), dic.lookup("controlword")
    with _open(args, dic) as link:
        def read_state():
            word = int(link.read(sw))
            return word, cia402.state_of(word)

        def describe(word, state):
            return "%s (statusword 0x%04X)" % (state or "an undefined state", word)

        word, state = read_state()
        if args.target is None:
            print(describe(word, state), file=out)
            return EXIT_OK
        target = cia402.TARGETS[args.target]
        if args.target == "fault-reset" and state != cia402.FAULT:
            print("not in FAULT, nothing to reset: %s" % describe(word, state), file=out)
            return EXIT_OK
        if target == cia402.QUICK_STOP_ACTIVE and state != cia402.OPERATION_ENABLED:
            print("operation not enabled, nothing to stop: %s" % describe(word, state), file=out)
            return EXIT_OK
        sent = None
        for _ in range(8):  # the longest walk is four transitions; waits in between count too
            if state == target:
                break
            if target == cia402.QUICK_STOP_ACTIVE and sent == cia402.CW_QUICK_STOP and \
                    state == cia402.SWITCH_ON_DISABLED:
                break  # the quick stop already ended: the drive leaves QUICK STOP ACTIVE by itself
            code = cia402.next_controlword(state, target) if state is not None else None
            if code is not None:
                if code == cia402.CW_FAULT_RESET:
                    link.write(cw, 0)  # bit 7 low first: the reset is its rising edge
                link.write(cw, code)
                sent = code
            before = state
            deadline = time.monotonic() + args.wait
            while True:
                word, state = read_state()
                if state != before or time.monotonic() >= deadline:
                    break
                time.sleep(0.02)
            if state == before:
                raise DtctuneError("the drive stayed in %s for %.1f s%s; wanted %s" % (
                    describe(word, state), args.wait,
                    " after controlword 0x%04X" % code if code is not None else "", target))
        if state != target and not (target == cia402.QUICK_STOP_ACTIVE and state == cia402.SWITCH_ON_DISABLED):
            raise DtctuneError("the drive went to %s; wanted %s" % (describe(word, state), target))
        print(describe(word, state), file=out)
    return EXIT_OK


def _telemetry_setup(args, dic, link, window_s=None):
    from . import telemetry
    tpdos = telemetry.read_layout(dic, None if args.from_eds else link)
    if not tpdos:
        raise DtctuneError("the drive has no enabled telemetry TPDO")
    cap = telemetry.Capture(link, tpdos, source_factory=lambda ids: telemetry.open_source(
        args.interface, args.channel, args.bitrate, ids))
    if window_s is not None:
        cap.open_window(window_s)
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
        # The window opens at the first frame of a whole telemetry cycle and lasts args.seconds
        # of the frames' receive timestamps: the wait for telemetry (and the switch to NMT
        # operational) is not counted against it.
        telemetry, tpdos, cap = _telemetry_setup(args, dic, link, window_s=args.seconds)
        clock = None
        try:
            _await_telemetry(args, telemetry, cap, link, tpdos, 2.0, lambda text: print(text, file=out))
            if not cap.wait_window_open(2.0):
                raise telemetry.no_telemetry_error(link, tpdos[:1], 2.0, can_start=not args.no_start)
            clock = _drive_clock(dic, link, tpdos)
            # Every frame received before t_until is in the socket once this PC's clock has
            # passed it (the kernel stamps a frame when it queues it); stop() reads that backlog.
            while time.time() < cap.t_until:
                time.sleep(min(0.25, max(0.0, cap.t_until - time.time())))
        finally:
            cap.stop(until=cap.t_until)
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
        span = _drive_span(frames, tpdos, clock) if clock else None
        if span:
            drive_s, wall_s = span
            print("drive clock: %.3f s in %.3f s of wall time (the drive ran at %.3fx real time; "
                  "first to last row, from their pdo_seq at %g Hz)"
                  % (drive_s, wall_s, drive_s / wall_s, clock[1]), file=out)
    return EXIT_OK


def _drive_clock(dic, link, tpdos):
    """(the cycle counter's signal, the telemetry rate in Hz of the drive's clock) when the drive
    maps a cycle counter (pdo_seq: +1 per telemetry cycle) and publishes its rate, else None.
    They give the drive's own time over the recorded rows, measured by the rows themselves (a
    simulated drive may run behind the wall clock)."""
    from .telemetry import columns
    seq = next((s for s in columns(tpdos) if s.name == "pdo_seq"), None)
    if seq is None:
        return None
    try:
        hz = float(link.read(dic.lookup("telemetry_hz")))
    except DtctuneError:
        return None
    return (seq, hz) if hz > 0 else None


def _drive_span(frames, tpdos, clock):
    """(drive seconds, receive-timestamp seconds) from the first to the last row that carries
    the cycle counter, or None with fewer than two such rows."""
    from .telemetry import rows
    seq_sig, hz = clock
    first = last = None
    cycles = 0
    for ts, row in rows(frames, tpdos):
        v = row.get(seq_sig.name)
        if v is None:
            continue
        v = int(v)
        if first is None:
            first = last = (ts, v)
            continue
        cycles += (v - last[1]) % (1 << seq_sig.bit_length)
        last = (ts, v)
    if first is None or last[0] <= first[0]:
        return None
    return cycles / hz, last[0] - first[0]


def cmd_scope(args, dic, out) -> int:
    from . import scope
    with _open(args, dic) as link:
        return scope.run(args, dic, link, out)


COMMANDS = {
    "list": cmd_list, "get": cmd_get, "set": cmd_set, "save": cmd_save,
    "restore-defaults": cmd_restore, "state": cmd_state, "monitor": cmd_monitor, "record": cmd_record, "scope": cmd_scope,
}


def main(argv: Optional[List[str]] = None, out=None) -> int:
    out = out or sys.stdout
    try:
        args = quick_args.parse(sys.argv[1:] if argv is None else argv)
        if args is None:  # --help, a usage error, or what the quick path leaves to argparse
            from .parser import build_parser
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
