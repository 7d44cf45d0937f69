#!/usr/bin/env python3
"""CAN benchmark of the drive over SocketCAN: SDO round-trip times and the telemetry rate the
drive sustains without lost frames.

  tests/can/uml/run_in_uml.sh -- .venv/bin/python tools/can_bench.py          # this machine (no CAN)
  .venv/bin/python tools/can_bench.py --channel vcan0                         # a host with vcan0

By default it starts the SIL itself (build/host/bin/dtc-sim --realtime --can CHANNEL on a
closed-loop scenario) and stops it at the end; --no-sim measures a drive that is already on the
bus (the real one). Figures:
  * SDO round trip: N expedited uploads, request sent -> response received, in one thread on a
    raw python-can socket (median, p90, p99, max), and the same through dtctune's own SDO client
    (its Link on a raw SocketCAN socket, with the SDO lock; JSON key "sdo_dtctune");
  * telemetry: for each rate, telemetry_hz is set, the TPDOs are received for S seconds and the
    drive's telemetry sequence counter (pdo_seq) tells the cycles lost anywhere between the
    drive and us; the drive's own tpdo_dropped counter tells the frames its transmit queue
    refused; the control tick counter (tel_tick) tells whether the SIL kept real time.
"""
from __future__ import annotations

import argparse
import json
import os
import socket
import statistics
import struct
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # the dtctune package next to this script, installed or not

import can  # noqa: E402

from dtctune.errors import DtctuneError  # noqa: E402
from dtctune.link import Link, SdoLock, lock_path, open_transport  # noqa: E402
from dtctune.od import Dictionary, find_eds  # noqa: E402
from dtctune.sil import Sil  # noqa: E402
from dtctune import telemetry  # noqa: E402

def tick_hz(link: Link, dic: Dictionary) -> float:
    """The drive's control-tick rate, from its period_s parameter (5000 Hz for 200 us)."""
    try:
        return 1.0 / float(link.read(dic.lookup("period_s")))
    except (DtctuneError, ZeroDivisionError):
        return 5000.0


def pct(sorted_vals, p):
    if not sorted_vals:
        return float("nan")
    k = min(len(sorted_vals) - 1, max(0, int(round(p / 100.0 * (len(sorted_vals) - 1)))))
    return sorted_vals[k]


def sdo_rtt_raw(channel: str, node: int, index: int, sub: int, n: int):
    """Expedited uploads on a raw socket: request -> matching response, seconds each."""
    bus = can.Bus(interface="socketcan", channel=channel,
                  can_filters=[{"can_id": 0x580 + node, "can_mask": 0x7FF}])
    req = can.Message(arbitration_id=0x600 + node, is_extended_id=False,
                      data=struct.pack("<BHB4x", 0x40, index, sub))
    out, aborts = [], 0
    try:
        for _ in range(n):
            t0 = time.perf_counter()
            bus.send(req)
            while True:
                m = bus.recv(1.0)
                if m is None:
                    raise DtctuneError("no SDO answer from node %d within 1 s" % node)
                if m.data[1:4] == req.data[1:4]:
                    break
            out.append(time.perf_counter() - t0)
            if m.data[0] == 0x80:
                aborts += 1
    finally:
        bus.shutdown()
    return out, aborts


def sdo_rtt_dtctune(link: Link, p, n: int):
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        link.read(p)
        out.append(time.perf_counter() - t0)
    return out


def ms_stats(vals):
    s = sorted(vals)
    return {"n": len(s), "median_ms": 1e3 * statistics.median(s), "p90_ms": 1e3 * pct(s, 90),
            "p99_ms": 1e3 * pct(s, 99), "max_ms": 1e3 * s[-1]}


def open_raw(channel: str, cobs):
    """A raw CAN socket for the TPDOs with a deep receive buffer (the drive may burst)."""
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    filt = b"".join(struct.pack("=II", c, 0x7FF) for c in cobs)
    s.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER, filt)
    for opt in (getattr(socket, "SO_RCVBUFFORCE", 33), socket.SO_RCVBUF):
        try:
            s.setsockopt(socket.SOL_SOCKET, opt, 16 << 20)
            break
        except OSError:
            continue
    s.bind((channel,))
    return s


def telemetry_run(link: Link, dic: Dictionary, channel: str, rate: int, seconds: float, tpdos):
    p_rate, p_drop, p_tick = dic.lookup("telemetry_hz"), dic.lookup("tpdo_dropped"), dic.lookup("tel_tick")
    seq_sig = next((s for t in tpdos for s in t.signals if s.name == "pdo_seq"), None)
    seq_tpdo = next((t for t in tpdos if seq_sig in t.signals), None)
    link.write(p_rate, rate)
    time.sleep(0.3)
    s = open_raw(channel, [t.cob_id for t in tpdos])
    try:
        t_drain = time.monotonic()
        while time.monotonic() - t_drain < 0.5:  # empty what queued while the rate changed
            try:  # (bounded: at high rates the drive may queue frames as fast as we take them)
                s.recv(16, socket.MSG_DONTWAIT)
            except BlockingIOError:
                break
        drop0, tick0 = int(link.read(p_drop)), int(link.read(p_tick))
        t_start = time.monotonic()
        counts = {t.cob_id: 0 for t in tpdos}
        seqs = []
        # Drain in batches (one wake-up per 20 ms, not per frame): on a single-CPU machine
        # per-frame wake-ups would take the CPU from the drive we are measuring.
        s.setblocking(False)
        while True:
            done = time.monotonic() - t_start >= seconds
            while True:
                try:
                    frame = s.recv(16)
                except BlockingIOError:
                    break
                cob, dlc = struct.unpack_from("=IB", frame)
                cob &= 0x7FF
                counts[cob] = counts.get(cob, 0) + 1
                if seq_tpdo is not None and cob == seq_tpdo.cob_id:
                    seqs.append(int(seq_sig.decode(frame[8:8 + dlc])))
            if done:
                break
            time.sleep(0.02)
        t_end = time.monotonic()
        drop1, tick1 = int(link.read(p_drop)), int(link.read(p_tick))
    finally:
        s.close()
    span = t_end - t_start
    lost = sum(((b - a) % 65536) - 1 for a, b in zip(seqs, seqs[1:]))
    cycles = len(seqs)
    drive_s = ((tick1 - tick0) % (1 << 32)) / tick_hz(link, dic)
    return {
        "rate_hz": rate,
        "drive_clock_cycle_hz": round(cycles / drive_s, 1) if drive_s > 0 else 0.0,
        "seconds": round(span, 3),
        "cycles_received": cycles,
        "cycles_lost": lost,
        "frames_received": sum(counts.values()),
        "measured_cycle_hz": round(cycles / span, 1) if span > 0 else 0.0,
        "drive_tx_dropped": drop1 - drop0,
        "sil_realtime_factor": round(drive_s / span, 3) if span > 0 else 0.0,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--channel", default="vcan0")
    ap.add_argument("--node", type=int, default=1)
    ap.add_argument("--eds", default=None)
    ap.add_argument("--no-sim", action="store_true", help="measure a drive already on the bus")
    ap.add_argument("--sim", default=None, help="dtc-sim binary (default build/host/bin/dtc-sim)")
    ap.add_argument("--scenario", default=None, help="closed-loop scenario for the SIL (default case1)")
    ap.add_argument("-n", type=int, default=1000, help="SDO uploads to time (default 1000)")
    ap.add_argument("--rates", default="100,1000,2000,5000", help="telemetry rates to try, Hz")
    ap.add_argument("--seconds", type=float, default=3.0, help="seconds per telemetry rate")
    ap.add_argument("--json", default=None, help="also write the figures to this JSON file")
    args = ap.parse_args(argv)

    sil = None
    try:
        dic = Dictionary(find_eds(args.eds), args.node)
        if not args.no_sim:
            nvm = tempfile.NamedTemporaryFile(prefix="can_bench_", suffix=".nvm", delete=False).name
            os.unlink(nvm)
            sil = Sil(args.channel, args.node, nvm=nvm, sim=args.sim, scenario=args.scenario)
            boot = sil.start(timeout_s=30.0)
            print("SIL: %s (boot-up after %.2f s)" % (" ".join(sil.command()), boot))
        results = {"channel": args.channel, "node": args.node}

        p_obj = dic.lookup("rbfn_k")
        raw, aborts = sdo_rtt_raw(args.channel, args.node, p_obj.index, p_obj.subindex, args.n)
        results["sdo_raw"] = ms_stats(raw)
        results["sdo_raw"]["aborts"] = aborts
        lock = SdoLock(lock_path("socketcan", args.channel, args.node))
        with Link(open_transport("socketcan", args.channel), dic, args.node, 1.0, args.channel, lock=lock) as link:
            results["sdo_dtctune"] = ms_stats(sdo_rtt_dtctune(link, p_obj, max(100, args.n // 5)))
            tpdos = telemetry.read_layout(dic, link)
            p_rate = dic.lookup("telemetry_hz")
            rate0 = int(link.read(p_rate))
            link.nmt("OPERATIONAL")
            results["telemetry"] = []
            try:
                for rate in [int(r) for r in args.rates.split(",") if r.strip()]:
                    results["telemetry"].append(telemetry_run(link, dic, args.channel, rate, args.seconds, tpdos))
            finally:
                link.write(p_rate, rate0)

        r, c = results["sdo_raw"], results["sdo_dtctune"]
        print("SDO expedited upload round trip (%s, %d x 0x%04X:%d):" % (args.channel, r["n"], p_obj.index,
                                                                          p_obj.subindex))
        print("  raw socket : median %.3f ms  p90 %.3f ms  p99 %.3f ms  max %.3f ms" %
              (r["median_ms"], r["p90_ms"], r["p99_ms"], r["max_ms"]))
        print("  dtctune    : median %.3f ms  p90 %.3f ms  p99 %.3f ms  max %.3f ms  (%d reads)" %
              (c["median_ms"], c["p90_ms"], c["p99_ms"], c["max_ms"], c["n"]))
        print("telemetry (%d TPDOs per cycle, %.0f s per rate):" % (len(tpdos), args.seconds))
        print("  %7s %9s %9s %8s %6s %9s %8s %9s" % ("set Hz", "wall Hz", "drive Hz", "cycles", "lost",
                                                      "frames/s", "tx drop", "SIL x rt"))
        for t in results["telemetry"]:
            print("  %7d %9.1f %9.1f %8d %6d %9.0f %8d %9.3f" % (
                t["rate_hz"], t["measured_cycle_hz"], t["drive_clock_cycle_hz"], t["cycles_received"],
                t["cycles_lost"], t["frames_received"] / t["seconds"], t["drive_tx_dropped"],
                t["sil_realtime_factor"]))
        print("  (wall Hz: cycles per second of wall time; drive Hz: per second of the drive's own clock;\n"
              "   lost: gaps in pdo_seq; tx drop: frames the drive's transmit queue refused;\n"
              "   SIL x rt: drive seconds per wall second, 1.0 = the SIL kept real time)")
        if args.json:
            with open(args.json, "w") as f:
                json.dump(results, f, indent=2)
    except DtctuneError as e:
        print("can_bench: error: %s" % e, file=sys.stderr)
        return 1
    except RuntimeError as e:
        print("can_bench: error: %s" % e, file=sys.stderr)
        return 1
    finally:
        if sil is not None:
            sil.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
