"""The drive's scope: arm it over SDO, wait for the capture, upload it, plot it.

Objects (from the parameter table): scope_channel_1..4 select telemetry signals by their
0x3000 subindex (0 = off), scope_trigger (0 manual, 1 speed-reference change, 2 fault),
scope_pretrigger (samples before the trigger), scope_decimation (ticks per sample),
scope_command (1 arm, 2 trigger now, 0 stop), scope_state (0 idle, 1 armed, 2 capturing,
3 done), scope_samples, scope_trigger_tick, and scope_data (DOMAIN: per enabled channel
`scope_samples` REAL32 values, oldest first; sample `scope_pretrigger` is the trigger).
"""
from __future__ import annotations

import csv
import os
import struct
import sys
import time
from pathlib import Path
from typing import List

from . import need_third_party
from .errors import DtctuneError, EXIT_NO_ANSWER
from .od import Dictionary, Param

TELEMETRY_INDEX = 0x3000
TRIGGERS = {"manual": 0, "ref": 1, "fault": 2}
STATE_WORDS = {0: "idle", 1: "armed", 2: "capturing", 3: "done"}
MAX_CHANNELS = 4
# The drive's control period: the scope samples once per tick times the decimation.
TICK_S = 200e-6


def _p(dic: Dictionary, name: str) -> Param:
    try:
        return dic.lookup(name)
    except DtctuneError:
        raise DtctuneError("the EDS %s has no %s: this drive has no scope dtctune knows" % (dic.path, name)) from None


TELEMETRY_PDO_INDEX = 0x3100
_PREFIXES = ("tel_", "tel.", "pdo_", "pdo.")


def _stem(name: str) -> str:
    low = name.lower()
    for pre in _PREFIXES:
        if low.startswith(pre):
            return low[len(pre):]
    return low


def telemetry_signals(dic: Dictionary) -> List[Param]:
    """The signals the scope can capture: the telemetry objects 0x3000:1.. in physical units."""
    return [q for q in dic.params if q.index == TELEMETRY_INDEX and q.subindex > 0]


def resolve_channel(dic: Dictionary, name: str) -> Param:
    """One channel name -> its telemetry signal (0x3000). Accepted, case-insensitive:
    the signal's name (tel_speed_est_rpm), the same without tel_ (speed_est_rpm), the name of
    the TPDO signal that `monitor` and `record` show for it (pdo_speed_est: the telemetry name
    with its unit suffix dropped), or the 0x3000 subindex (2). A parameter of the same name
    (e.g. speed_ref_rpm, 0x2000:1, the set point) is not a channel: its telemetry signal is."""
    n = name.strip()
    sigs = telemetry_signals(dic)
    if n.isdigit():
        for q in sigs:
            if q.subindex == int(n):
                return q
    else:
        low = n.lower()
        for q in sigs:
            if q.name.lower() == low:
                return q
        stem = _stem(n)
        exact = [q for q in sigs if _stem(q.name) == stem]
        if len(exact) == 1:
            return exact[0]
        # pdo_te_ref -> tel_te_ref_Nm: the telemetry name is the stem plus one unit token
        near = [q for q in sigs if _stem(q.name).startswith(stem + "_")
                and "_" not in _stem(q.name)[len(stem) + 1:] and "." not in _stem(q.name)[len(stem) + 1:]]
        if len(near) == 1:
            return near[0]
    choices = ", ".join(q.name[4:] if q.name.lower().startswith(_PREFIXES[:2]) else q.name for q in sigs)
    what = "'%s' is not a telemetry signal" % n
    try:
        p = dic.lookup(n)
        if p.index == TELEMETRY_PDO_INDEX:
            what = "'%s' is a TPDO signal without a scope channel" % n
        elif p.index != TELEMETRY_INDEX:
            what = "'%s' is a parameter (%s), not a telemetry signal" % (n, p.address)
    except DtctuneError:
        pass
    raise DtctuneError("--channels: %s; valid channels (also with the tel_ prefix, as the pdo_* names "
                       "of monitor/record, or as 0x%04X subindex numbers): %s" % (what, TELEMETRY_INDEX, choices))


def resolve_channels(dic: Dictionary, spec: str) -> List[Param]:
    """A comma-separated channel list -> telemetry params (see resolve_channel)."""
    names = [s.strip() for s in spec.split(",") if s.strip()]
    if not names:
        raise DtctuneError("--channels: give 1 to %d telemetry signals" % MAX_CHANNELS)
    if len(names) > MAX_CHANNELS:
        raise DtctuneError("--channels: at most %d channels, got %d" % (MAX_CHANNELS, len(names)))
    return [resolve_channel(dic, n) for n in names]


def decode(data: bytes, n_channels: int, samples: int) -> List[List[float]]:
    need = 4 * n_channels * samples
    if len(data) != need:
        raise DtctuneError("scope data is %d bytes, expected %d (%d channels x %d samples x 4)"
                           % (len(data), need, n_channels, samples), EXIT_NO_ANSWER)
    vals = struct.unpack("<%df" % (n_channels * samples), data)
    return [list(vals[c * samples:(c + 1) * samples]) for c in range(n_channels)]


def run(args, dic: Dictionary, link, out) -> int:
    chans = resolve_channels(dic, args.channels)
    p_chan = [_p(dic, "scope_channel_%d" % (i + 1)) for i in range(MAX_CHANNELS)]
    p_trig, p_pre = _p(dic, "scope_trigger"), _p(dic, "scope_pretrigger")
    p_dec, p_cmd, p_state = _p(dic, "scope_decimation"), _p(dic, "scope_command"), _p(dic, "scope_state")
    p_samples, p_tick, p_data = _p(dic, "scope_samples"), _p(dic, "scope_trigger_tick"), _p(dic, "scope_data")
    if args.png is None and args.csv is None:
        raise DtctuneError("scope: give --png OUT and/or --csv OUT")

    samples = int(link.read(p_samples))
    if args.pretrigger is not None:
        if not 0.0 <= args.pretrigger < 1.0:
            raise DtctuneError("--pretrigger must be a fraction 0..1, got %g" % args.pretrigger)
        pre_raw = int(round(args.pretrigger * samples))
        p_pre.check(pre_raw)
    if args.decimation is not None:
        p_dec.check(args.decimation)

    # Configure (stop a previous capture first: settings are read at arming).
    link.write(p_cmd, 0)
    for i in range(MAX_CHANNELS):
        link.write(p_chan[i], chans[i].subindex if i < len(chans) else 0)
    link.write(p_trig, TRIGGERS[args.trigger])
    if args.pretrigger is not None:
        link.write(p_pre, pre_raw)
    if args.decimation is not None:
        link.write(p_dec, args.decimation)
    pretrigger = int(link.read(p_pre))
    decimation = int(link.read(p_dec))

    link.write(p_cmd, 1)  # arm
    if args.trigger == "manual":
        # Let the pre-trigger part fill before triggering, so it holds real samples.
        time.sleep(pretrigger * decimation * TICK_S * 1.2 + 0.05)
        link.write(p_cmd, 2)
    else:
        what = "a speed-reference change" if args.trigger == "ref" else "a fault"
        print("scope armed: waiting up to %.0f s for %s" % (args.wait, what), file=out, flush=True)

    if getattr(args, "background", False):
        out.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid > 0:
            print("scope: process %d finishes the capture (%s) in the background"
                  % (pid, ", ".join(x for x in (args.png, args.csv) if x)), file=out, flush=True)
            return 0
        # The background process: its own session (a closing terminal does not end it), its own
        # open lock file (flock belongs to the open file, which fork shared with the parent).
        status = 1
        try:
            os.setsid()
            link.lock.close()
            status = _finish(args, link, out, chans, samples, pretrigger, decimation,
                             p_cmd, p_state, p_tick, p_data)
        except DtctuneError as e:
            print("dtctune: error: scope (background): %s" % e, file=sys.stderr)
            status = e.status
        except BaseException as e:  # noqa: BLE001 - nothing may escape a forked child
            print("dtctune: error: scope (background): %s" % e, file=sys.stderr)
        finally:
            try:
                link.close()
                out.flush()
                sys.stderr.flush()
            finally:
                os._exit(status)
    return _finish(args, link, out, chans, samples, pretrigger, decimation, p_cmd, p_state, p_tick, p_data)


def _finish(args, link, out, chans, samples, pretrigger, decimation, p_cmd, p_state, p_tick, p_data) -> int:
    """Wait for the capture, upload it, write the outputs."""
    t_end = time.monotonic() + args.wait + samples * decimation * TICK_S
    state = None
    while time.monotonic() < t_end:
        state = int(link.read(p_state))
        if state == 3:
            break
        time.sleep(0.05)
    if state != 3:
        link.write(p_cmd, 0)
        raise DtctuneError("scope: no capture within %.0f s (state %s); the trigger did not come"
                           % (args.wait, STATE_WORDS.get(state, state)), EXIT_NO_ANSWER)
    trig_tick = int(link.read(p_tick))
    data = link.upload_block(p_data.index, p_data.subindex, "the upload of the scope data (%s)" % p_data.address)
    traces = decode(data, len(chans), samples)

    dt = decimation * TICK_S
    t = [(k - pretrigger) * dt for k in range(samples)]
    if args.csv:
        _write_csv(Path(args.csv), t, chans, traces)
    if args.png:
        title = "drive scope, node %d: trigger %s at tick %d, %d samples every %g ms" % (
            args.node, args.trigger, trig_tick, samples, dt * 1e3)
        plot(Path(args.png), t, chans, traces, title)
    print("scope: %d channels x %d samples captured (trigger at tick %d)%s%s"
          % (len(chans), samples, trig_tick, "; plot " + args.png if args.png else "",
             "; csv " + args.csv if args.csv else ""), file=out)
    return 0


def _write_csv(dest: Path, t, chans, traces) -> None:
    tmp = dest.with_name(dest.name + ".partial")
    try:
        with open(tmp, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["t_s"] + [c.name for c in chans])
            for k in range(len(t)):
                w.writerow(["%.6f" % t[k]] + ["%.7g" % tr[k] for tr in traces])
        os.replace(tmp, dest)
    except OSError as e:
        raise DtctuneError("cannot write %s: %s" % (dest, e.strerror or e)) from None


def plot(dest: Path, t, chans, traces, title: str) -> None:
    need_third_party()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(chans)
    fig, axes = plt.subplots(n, 1, figsize=(8, 1.8 * n + 0.8), sharex=True, squeeze=False)
    t_ms = [x * 1e3 for x in t]
    for i, (c, tr) in enumerate(zip(chans, traces)):
        ax = axes[i][0]
        ax.plot(t_ms, tr, lw=0.8, color="C%d" % i)
        ax.axvline(0.0, color="0.4", ls=":", lw=0.8)
        ax.set_ylabel("%s\n[%s]" % (c.name, c.unit) if c.unit else c.name, fontsize=8)
        ax.grid(True, lw=0.3)
        ax.tick_params(labelsize=7)
    axes[-1][0].set_xlabel("time from trigger [ms]", fontsize=8)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    tmp = dest.with_name(dest.name + ".partial.png")
    try:
        fig.savefig(tmp, dpi=110)
        os.replace(tmp, dest)
    except OSError as e:
        raise DtctuneError("cannot write %s: %s" % (dest, e.strerror or e)) from None
    finally:
        plt.close(fig)
