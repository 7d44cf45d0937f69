"""Telemetry TPDOs: their layout (from the drive, or the EDS), decoding, capture, rates."""
from __future__ import annotations

import csv
import struct
import threading
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, TextIO, Tuple

from .errors import DtctuneError, EXIT_NO_ANSWER, EXIT_REFUSED
from .od import Dictionary, Param

TPDO_COMM = 0x1800     # + n: communication parameters of TPDO n+1 (sub1 COB-ID, sub2 type, sub5 event timer)
TPDO_MAP = 0x1A00      # + n: mapping (sub0 count, sub1.. entries index<<16 | sub<<8 | bits)
MAX_TPDOS = 512
COB_INVALID = 0x80000000


@dataclass
class Signal:
    param: Param
    bit_offset: int
    bit_length: int

    @property
    def name(self) -> str:
        return self.param.name

    def decode(self, data: bytes):
        """The physical value of this signal in a PDO payload (None when the frame is too short)."""
        end = self.bit_offset + self.bit_length
        if end > 8 * len(data):
            return None
        if self.bit_offset % 8 == 0 and self.bit_length % 8 == 0:
            chunk = bytes(data[self.bit_offset // 8:end // 8])
        else:  # bit fields: shift out and re-pack into whole bytes
            word = int.from_bytes(bytes(data), "little")
            v = (word >> self.bit_offset) & ((1 << self.bit_length) - 1)
            chunk = v.to_bytes((self.bit_length + 7) // 8, "little")
        return self.param.to_phys(self.param.var.decode_raw(chunk))


@dataclass
class Tpdo:
    number: int            # 1-based
    cob_id: int
    transmission: Optional[int]
    signals: List[Signal] = field(default_factory=list)


def _u32(data: bytes) -> int:
    return int.from_bytes(bytes(data[:4]).ljust(4, b"\0"), "little")


def read_layout(dic: Dictionary, link=None) -> List[Tpdo]:
    """The enabled TPDOs and their signals: read from the drive when `link` is given, else the EDS."""
    out: List[Tpdo] = []
    for n in range(MAX_TPDOS):
        comm, mapping = TPDO_COMM + n, TPDO_MAP + n
        if not dic.has_object(comm) or not dic.has_object(mapping):
            if n >= 4:
                break  # the EDS lists TPDOs contiguously from 0x1800
            continue

        def value(index: int, sub: int) -> Optional[int]:
            if link is not None:
                try:
                    return _u32(link.upload(index, sub, "the read of TPDO%d's layout (0x%04X:%d)"
                                            % (n + 1, index, sub)))
                except DtctuneError as e:
                    if e.status != EXIT_REFUSED:
                        raise
                    # the drive does not serve this entry: its EDS value is all there is
            v = dic.default(index, sub)
            return int(v) if isinstance(v, (int, float)) else None

        cob = value(comm, 1)
        if cob is None or cob & COB_INVALID:
            continue
        try:
            ttype = value(comm, 2)
        except DtctuneError:
            ttype = None
        count = value(mapping, 0) or 0
        t = Tpdo(n + 1, cob & 0x7FF, ttype)
        offset = 0
        for sub in range(1, count + 1):
            entry = value(mapping, sub) or 0
            index, subindex, bits = entry >> 16, (entry >> 8) & 0xFF, entry & 0xFF
            p = dic._by_addr.get((index, subindex))
            if p is None:
                raise DtctuneError("TPDO%d maps 0x%04X:%d, which the EDS %s does not describe "
                                   "(EDS and drive out of step?)" % (n + 1, index, subindex, dic.path))
            t.signals.append(Signal(p, offset, bits))
            offset += bits
        if t.signals:
            out.append(t)
    return out


class PythonCanSource:
    """TPDO frames from a python-can bus of our own (any interface)."""

    def __init__(self, bus, can_ids):
        self.bus = bus
        self.ids = set(can_ids)
        try:
            bus.set_filters([{"can_id": c, "can_mask": 0x7FF, "extended": False} for c in sorted(self.ids)])
        except (NotImplementedError, OSError):
            pass

    def drain(self, out: list, max_frames: int) -> int:
        """Append up to max_frames waiting frames as (timestamp, id, data); return how many
        were read (fewer than max_frames: none is left)."""
        for n in range(max_frames):
            m = self.bus.recv(0)
            if m is None:
                return n
            if not (m.is_error_frame or m.is_remote_frame) and m.arbitration_id in self.ids:
                out.append((m.timestamp, m.arbitration_id, bytes(m.data)))
        return max_frames

    def close(self) -> None:
        self.bus.shutdown()


class SocketcanSource:
    """TPDO frames straight from a raw SocketCAN socket: a kernel filter, kernel receive
    timestamps, one system call per frame (python-can's generic path takes about three times
    the CPU per frame, which at kHz rates matters on a small machine)."""

    SO_TIMESTAMPNS = 35
    SO_RCVBUFFORCE = 33
    SO_RXQ_OVFL = 40
    FRAME = struct.Struct("=IB3x8s")

    def __init__(self, channel: str, can_ids):
        import socket
        self.ids = set(can_ids)
        self.kernel_drops = 0  # frames the kernel dropped because our receive buffer was full
        s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        try:
            s.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                         b"".join(struct.pack("=II", c, 0x7FF | 0xC0000000) for c in sorted(self.ids)))
            s.setsockopt(socket.SOL_SOCKET, self.SO_TIMESTAMPNS, 1)
            s.setsockopt(socket.SOL_SOCKET, self.SO_RXQ_OVFL, 1)
            # Room for bursts and for the times this process is not scheduled: several seconds
            # of telemetry. Beyond net.core.rmem_max only with CAP_NET_ADMIN (FORCE).
            for opt in (self.SO_RCVBUFFORCE, socket.SO_RCVBUF):
                try:
                    s.setsockopt(socket.SOL_SOCKET, opt, 8 << 20)
                    break
                except OSError:
                    continue
            s.bind((channel,))
            s.setblocking(False)
        except OSError:
            s.close()
            raise
        self.sock = s

    def drain(self, out: list, max_frames: int) -> int:
        """Like PythonCanSource.drain: at most max_frames, so a sender faster than this
        process cannot keep the caller in here for ever."""
        for n in range(max_frames):
            try:
                data, anc, _flags, _addr = self.sock.recvmsg(16, 128)
            except BlockingIOError:
                return n
            if len(data) < 16:
                continue
            can_id, dlc, payload = self.FRAME.unpack(data)
            ts = None
            for level, kind, blob in anc:
                if kind == self.SO_TIMESTAMPNS and len(blob) >= 16:
                    sec, nsec = struct.unpack_from("=qq", blob)
                    ts = sec + nsec * 1e-9
                elif kind == self.SO_RXQ_OVFL and len(blob) >= 4:
                    self.kernel_drops = struct.unpack_from("=I", blob)[0]
            if ts is None:
                ts = time.time()
            cid = can_id & 0x7FF
            if cid in self.ids:
                out.append((ts, cid, payload[:min(dlc, 8)]))
        return max_frames

    def close(self) -> None:
        self.sock.close()


def open_source(interface: str, channel: str, bitrate, can_ids):
    """The cheapest frame source for this interface."""
    if interface == "socketcan":
        try:
            return SocketcanSource(channel, can_ids)
        except (OSError, AttributeError):
            pass  # let python-can report the problem in its words
    from .link import open_bus
    return PythonCanSource(open_bus(interface, channel, bitrate), can_ids)


class Capture:
    """Collects TPDO frames (with their receive timestamps) on a socket of its own.

    The frames are drained in batches every `poll_s` rather than one wake-up per frame: at
    kHz telemetry rates a per-frame wake-up costs more CPU than the frames themselves (and on a
    single-CPU machine takes it from the drive simulation). The socket buffers in between.

    A recording window (`open_window` or `window_from`, and `stop(until=...)`) is judged by the
    frames' receive timestamps, not by when this process gets to them: on a slow PC the frames
    wait in the (deep) socket buffer and are still counted in the window they arrived in, and
    stop() reads on until a frame from after the window shows that the window is complete.
    """

    BATCH = 256           # frames per drain call
    STOP_DRAIN_S = 10.0   # after stop(until=...), read the backlog for at most this long
    QUIET_S = 2.0         # ... and stop early when no frame came for this long (the sender stopped)

    def __init__(self, link, tpdos: Sequence[Tpdo], source_factory=None, poll_s: float = 0.02):
        self.link = link
        self.tpdos = list(tpdos)
        self.by_cob: Dict[int, Tpdo] = {t.cob_id: t for t in tpdos}
        self.frames: List[Tuple[float, int, bytes]] = []
        self.counts: Dict[int, int] = {t.cob_id: 0 for t in tpdos}
        self.first: Dict[int, float] = {}
        self.last: Dict[int, float] = {}
        self.latest: Dict[int, bytes] = {}
        self.keep = True
        self.poll_s = poll_s
        self._factory = source_factory
        self._source = None
        self._thread: Optional[threading.Thread] = None
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._seen = threading.Event()
        self._t_from: Optional[float] = None   # window start (receive timestamp), None: all
        self._t_until: Optional[float] = None  # window end, set by stop(until=...) or open_window
        self._reached_until = False
        self._window_s: Optional[float] = None  # open_window: its length, s of receive timestamps
        self._window_cob: Optional[int] = None  # the TPDO whose first frame opens it
        self._opened = threading.Event()

    def open_window(self, seconds: float) -> None:
        """Record `seconds` of receive timestamps from the first frame of a whole telemetry
        cycle (the first TPDO in cycle order) received from now on: the window is judged by the
        frames alone, so the wait for the first frame (or for the drive to reach NMT
        operational) takes nothing from it; it holds the whole cycles that begin within it, and no clock of this PC is compared with the
        kernel's receive timestamps at its start. Call before start(); t_from and t_until are
        known once a frame opened it (wait_window_open)."""
        with self._lock:
            self._window_s = float(seconds)
            self._window_cob = self.tpdos[0].cob_id if self.tpdos else None
            self._t_from = None
            self._t_until = None
            self._opened.clear()

    def wait_window_open(self, timeout_s: float) -> bool:
        return self._opened.wait(timeout_s)

    @property
    def t_from(self) -> Optional[float]:
        return self._t_from

    @property
    def t_until(self) -> Optional[float]:
        return self._t_until

    def window_from(self, t_from: float) -> None:
        """Count only frames received at or after t_from (time.time() clock, as the kernel's
        receive timestamps), dropping what was collected so far."""
        with self._lock:
            self._t_from = t_from
            self.frames.clear()
            self.counts = {c: 0 for c in self.counts}
            self.first.clear()
            self.last.clear()

    def _on_frame(self, can_id: int, data, timestamp: float) -> None:
        d = bytes(data)
        with self._lock:
            if self._window_s is not None and self._t_from is None:
                if can_id != self._window_cob:
                    return  # the rest of a cycle that began before the window
                self._t_from = timestamp
                self._t_until = timestamp + self._window_s
                self._opened.set()
            if self._t_until is not None and timestamp >= self._t_until:
                # The window holds whole cycles: those whose first TPDO came before its end. The
                # rest of the last one may be stamped after the end (a sender that spreads a
                # cycle's frames, a busy machine); the next cycle's first TPDO ends it.
                if self._window_s is None or can_id == self._window_cob or self._reached_until:
                    self._reached_until = True
                    return
            if self._t_from is not None and timestamp < self._t_from:
                return
            if self.keep:
                self.frames.append((timestamp, can_id, d))
            self.counts[can_id] += 1
            self.first.setdefault(can_id, timestamp)
            self.last[can_id] = timestamp
            self.latest[can_id] = d
            if len(self.latest) == len(self.by_cob):
                self._seen.set()

    def _drop_received_from(self, until: float) -> None:
        """Forget the kept frames received at or after `until` (in a window: from the first cycle
        that begins at or after it; call with the lock held): the
        capture thread may have read past the window's end before stop() named it (a sender
        faster than this process, or a caller that stops late). Their counts and first/last
        times go with them. With keep off the frames are not stored, so the counts cannot be
        corrected: they may include frames read after `until` before stop()."""
        if not self.keep or not any(f[0] >= until for f in self.frames):
            return
        if self._window_s is not None:  # whole cycles (_on_frame): cut at the next cycle's start
            cut = next((i for i, f in enumerate(self.frames) if f[0] >= until and f[1] == self._window_cob),
                       len(self.frames))
            if cut == len(self.frames):
                return
            kept, dropped = self.frames[:cut], self.frames[cut:]
        else:
            kept = [f for f in self.frames if f[0] < until]
            dropped = [f for f in self.frames if f[0] >= until]
        for _, cid, _ in dropped:
            self.counts[cid] -= 1
        self.frames = kept
        self.first.clear()
        self.last.clear()
        for ts, cid, _ in kept:
            self.first.setdefault(cid, ts)
            self.last[cid] = ts
        self._reached_until = True

    def start(self) -> None:
        if self._factory is None:
            raise ValueError("Capture needs a source_factory (e.g. open_source)")
        self._source = self._factory(list(self.by_cob))
        self._thread = threading.Thread(target=self._run, name="dtctune-capture", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        batch: list = []
        stop_deadline = None
        last_frame = time.monotonic()
        while True:
            stopping = self._stop.is_set()
            if stopping and stop_deadline is None:
                stop_deadline = time.monotonic() + self.STOP_DRAIN_S
            try:
                n = self._source.drain(batch, self.BATCH)
            except Exception:  # the interface went away: stop quietly, the caller reports no data
                return
            for ts, cid, data in batch:
                self._on_frame(cid, data, ts)
            batch.clear()
            now = time.monotonic()
            if n > 0:
                last_frame = now
            if stopping:
                # Read up to the end of the window: until a frame stamped at or after it (frames
                # reach the socket in the order they were stamped, so none of the window is still
                # on its way), or no frame for QUIET_S (the drive stopped sending). An empty socket
                # is no proof: a frame is stamped when the sender queues it and reaches the
                # socket later, in a busy User-Mode Linux up to seconds later.
                if self._t_until is None or self._reached_until or now > stop_deadline:
                    return
                if n < self.BATCH:
                    if now - last_frame > self.QUIET_S:
                        return
                    time.sleep(self.poll_s)
                continue
            if n < self.BATCH:
                self._stop.wait(self.poll_s)

    @property
    def kernel_drops(self) -> int:
        """Frames lost in this PC's receive buffer (SocketCAN only), since start()."""
        return getattr(self._source, "kernel_drops", 0) if self._source is not None else self._drops

    _drops = 0

    def stop(self, until: Optional[float] = None) -> None:
        """Stop capturing; with `until` (a receive timestamp), first read what the socket
        still holds from before that instant."""
        with self._lock:
            self._t_until = until
            if until is not None:
                self._drop_received_from(until)
        if self._source is not None:
            self._drops = getattr(self._source, "kernel_drops", 0)
        if self._source is None:
            return
        self._stop.set()
        if self._thread is not None:
            self._thread.join(self.STOP_DRAIN_S + 2.0)
        try:
            self._source.close()
        except Exception:
            pass
        self._source = None

    def wait_all_seen(self, timeout_s: float) -> bool:
        return self._seen.wait(timeout_s)

    def rate_hz(self, cob: int) -> Optional[float]:
        with self._lock:
            n = self.counts.get(cob, 0)
            if n < 2:
                return None
            span = self.last[cob] - self.first[cob]
        return (n - 1) / span if span > 0 else None

    def snapshot(self) -> Dict[int, bytes]:
        with self._lock:
            return dict(self.latest)


def no_telemetry_error(link, tpdos: Sequence[Tpdo], waited_s: float, can_start: bool = True) -> DtctuneError:
    cobs = ", ".join("0x%03X" % t.cob_id for t in tpdos)
    if can_start:
        why = "it was switched to NMT operational, where they are sent: is telemetry mapped and the drive running?"
    else:
        why = "the drive sends them only in NMT operational; drop --no-start (or add --start) to switch it there"
    return DtctuneError("no telemetry from node %d within %.1f s (TPDOs %s): %s"
                        % (link.node_id, waited_s, cobs, why), EXIT_NO_ANSWER)


def columns(tpdos: Sequence[Tpdo]) -> List[Signal]:
    return [s for t in tpdos for s in t.signals]


def rows(frames: Sequence[Tuple[float, int, bytes]], tpdos: Sequence[Tpdo]):
    """Group frames into rows, one per telemetry period: a row ends when a TPDO repeats.

    Yields (t_s of the row's first frame, {signal name: value}). A TPDO lost on the bus leaves
    its signals empty in that row rather than repeating old values.
    """
    by_cob = {t.cob_id: t for t in tpdos}
    # A cycle's TPDOs go out in order: start at the first TPDO so rows are whole cycles.
    first_cob = tpdos[0].cob_id if tpdos else None
    k0 = next((k for k, f in enumerate(frames) if f[1] == first_cob), len(frames))
    frames = frames[k0:]
    row: Dict[str, object] = {}
    have: set = set()
    t_row = None
    for ts, cob, data in frames:
        t = by_cob.get(cob)
        if t is None:
            continue
        if cob in have:
            yield t_row, row
            row, have, t_row = {}, set(), None
        if t_row is None:
            t_row = ts
        have.add(cob)
        for s in t.signals:
            row[s.name] = s.decode(data)
    if have:
        yield t_row, row


def write_csv(out: TextIO, frames, tpdos: Sequence[Tpdo]) -> int:
    """CSV: t_s (seconds since the first row, from the receive timestamps), then every signal."""
    cols = [s.name for s in columns(tpdos)]
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["t_s"] + cols)
    t0 = None
    n = 0
    for ts, row in rows(frames, tpdos):
        if t0 is None:
            t0 = ts
        w.writerow(["%.6f" % (ts - t0)] + [_csv_value(row.get(c)) for c in cols])
        n += 1
    return n


def _csv_value(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return "%.7g" % v
    if isinstance(v, bool):
        return "1" if v else "0"
    return str(v)


def render_table(tpdos: Sequence[Tpdo], cap: Capture, title: str) -> str:
    """The monitor's table: one line per signal with its TPDO's measured rate."""
    snap = cap.snapshot()
    lines = [title, "%-32s %14s  %-8s %-6s %9s" % ("signal", "value", "unit", "TPDO", "rate Hz")]
    for t in tpdos:
        data = snap.get(t.cob_id)
        rate = cap.rate_hz(t.cob_id)
        rate_s = "%9.1f" % rate if rate else "%9s" % "-"
        for s in t.signals:
            v = s.decode(data) if data is not None else None
            if v is None:
                vs = "-"
            elif isinstance(v, float):
                vs = "%.6g" % v
            else:
                vs = str(v)
            lines.append("%-32s %14s  %-8s %-6s %s" % (s.name, vs, s.param.unit, "%d" % t.number, rate_s))
    return "\n".join(lines)


def wait_first(cap: Capture, link, tpdos: Sequence[Tpdo], timeout_s: float, can_start: bool = False) -> None:
    """Wait until every TPDO was seen once, or raise the 'no telemetry' error."""
    t0 = time.monotonic()
    if not cap.wait_all_seen(timeout_s):
        if not cap.snapshot():
            waited = time.monotonic() - t0
            try:  # this drive's rate parameter: 0 switches the telemetry off
                p = link.dic.lookup("telemetry_hz")
                if int(link.read(p)) == 0:
                    raise DtctuneError("no telemetry from node %d: it is switched off (telemetry_hz = 0); "
                                       "dtctune set telemetry_hz 100" % link.node_id, EXIT_NO_ANSWER)
            except DtctuneError as e:
                if "switched off" in str(e):
                    raise
            raise no_telemetry_error(link, tpdos, waited, can_start)
        # Some TPDOs arrive, others not: report what is missing but go on with what we have.
