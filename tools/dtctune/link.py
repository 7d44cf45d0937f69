"""The CAN link to one drive: SDO access with plain errors, NMT, and the SDO lock.

The SDO client (CiA 301 expedited and segmented transfers) is dtctune's own, on one of two
transports: a raw SocketCAN socket (the standard library only, for `--interface socketcan`: no
python-can or canopen import, so a command starts in a fraction of a second) or a python-can bus
(every other interface; python-can is imported only then).

Large objects (the scope capture) go by block upload (CiA 301 block transfer: up to 127
segments per acknowledge, CRC-16 checked), falling back to a segmented upload when the server
refuses the block protocol.

The drive has one SDO server channel (requests 0x600 + id, answers 0x580 + id). Two clients
using it at once receive each other's answers, so every SDO transfer of dtctune holds an
advisory lock (fcntl.flock) on a file per interface, channel and node: two dtctune processes on
the same bus take turns per transfer instead of colliding (see SdoLock).
"""
from __future__ import annotations

import errno
import os
import select
import struct
import time

from . import abort_codes, need_third_party
from .errors import DtctuneError, EXIT_NO_ANSWER, EXIT_REFUSED, EXIT_USAGE
from .od import Dictionary, Param

# CiA 301 signatures for store (0x1010) and restore (0x1011): "save" and "load" in ASCII,
# sent as UNSIGNED32 little-endian.
SIGNATURE_SAVE = 0x65766173
SIGNATURE_LOAD = 0x64616F6C
OBJ_STORE = 0x1010
OBJ_RESTORE = 0x1011

NMT_COMMANDS = {"OPERATIONAL": 0x01, "STOPPED": 0x02, "PRE-OPERATIONAL": 0x80, "RESET": 0x81,
                "RESET COMMUNICATION": 0x82}

ABORT_TOGGLE = 0x05030000
ABORT_TIMEOUT = 0x05040000
ABORT_COMMAND = 0x05040001
ABORT_BLKSIZE = 0x05040002
ABORT_SEQNO = 0x05040003
ABORT_CRC = 0x05040004
ABORT_MEMORY = 0x05040005
BLOCK_SEGMENTS = 127  # segments per block dtctune accepts (the protocol's largest)


def crc16(data: bytes, crc: int = 0) -> int:
    """CRC-16 of CiA 301 block transfers: CCITT polynomial 0x1021, initial 0, no reflection."""
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc
MAX_UPLOAD = 1 << 20  # a segmented upload longer than this is a confused server: abort it

# How long a command waits for another dtctune's SDO transfer to finish (a scope upload of
# 4 x 1024 samples takes several seconds inside User-Mode Linux).
LOCK_WAIT_S = float(os.environ.get("DTCTUNE_LOCK_WAIT", "60"))


# ------------------------------------------------------------------------------ errors

class SdoAbort(Exception):
    def __init__(self, code: int):
        super().__init__("SDO abort 0x%08X" % code)
        self.code = code


class SdoTimeout(Exception):
    pass


class SdoProtocolError(Exception):
    pass


# ------------------------------------------------------------------------------ transports

_CAN_FRAME = struct.Struct("=IB3x8s")


def _socketcan_error(e: OSError, channel: str) -> DtctuneError:
    if e.errno == errno.EAFNOSUPPORT:
        return DtctuneError("SocketCAN is not available in this kernel (errno 97); use a kernel "
                            "with CAN/vcan, or run inside tests/can/uml/run_in_uml.sh", EXIT_NO_ANSWER)
    if e.errno == errno.ENODEV:
        return DtctuneError("CAN interface %s does not exist (create it: ip link add dev %s type vcan; "
                            "ip link set up %s)" % (channel, channel, channel), EXIT_NO_ANSWER)
    if e.errno == errno.ENETDOWN:
        return DtctuneError("CAN interface %s is down (ip link set up %s)" % (channel, channel), EXIT_NO_ANSWER)
    return DtctuneError("cannot use CAN interface %s (socketcan): %s" % (channel, e.strerror or e), EXIT_NO_ANSWER)


class SocketcanTransport:
    """Standard CAN frames on a raw SocketCAN socket, only the identifiers asked for."""

    def __init__(self, channel: str):
        # The C module, not `socket`: socket.py builds its enums (and imports enum, selectors,
        # array) at import, 0.08 s of a command's start-up inside User-Mode Linux.
        import _socket as socket
        self.channel = channel
        try:
            s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        except (OSError, AttributeError) as e:
            if isinstance(e, AttributeError):
                raise DtctuneError("SocketCAN is not available on this system", EXIT_NO_ANSWER) from None
            raise _socketcan_error(e, channel) from None
        try:
            s.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER, b"")  # nothing until set_ids
            s.bind((channel,))
        except OSError as e:
            s.close()
            raise _socketcan_error(e, channel) from None
        self._socket_mod = socket
        self.sock = s

    def set_ids(self, ids) -> None:
        flt = b"".join(struct.pack("=II", c, 0x7FF | 0xC0000000) for c in sorted(ids))
        self.sock.setsockopt(self._socket_mod.SOL_CAN_RAW, self._socket_mod.CAN_RAW_FILTER, flt)

    def send(self, can_id: int, data: bytes) -> None:
        try:
            self.sock.send(_CAN_FRAME.pack(can_id, len(data), bytes(data).ljust(8, b"\0")))
        except OSError as e:
            if e.errno == errno.ENOBUFS:  # transmit queue full: wait a little once
                time.sleep(0.01)
                self.sock.send(_CAN_FRAME.pack(can_id, len(data), bytes(data).ljust(8, b"\0")))
                return
            raise

    def recv(self, timeout_s: float):
        """(can_id, data) of the next frame, or None after timeout_s. A frame already waiting
        is taken without select (a block upload brings 127 at once)."""
        try:
            frame = self.sock.recv(16, self._socket_mod.MSG_DONTWAIT)
        except BlockingIOError:
            r, _, _ = select.select([self.sock], [], [], max(0.0, timeout_s))
            if not r:
                return None
            frame = self.sock.recv(16)
        can_id, dlc, payload = _CAN_FRAME.unpack(frame)
        if can_id & 0x60000000:  # RTR or error frame
            return (None, b"")
        return (can_id & 0x7FF, payload[:min(dlc, 8)])

    def flush(self) -> None:
        while True:
            r, _, _ = select.select([self.sock], [], [], 0)
            if not r:
                return
            self.sock.recv(16)

    def close(self) -> None:
        self.sock.close()


class PythonCanTransport:
    """The same on a python-can bus (any interface python-can knows)."""

    def __init__(self, bus, channel: str = "?"):
        need_third_party()
        import can
        self._can = can
        self.bus = bus
        self.channel = channel

    def set_ids(self, ids) -> None:
        try:
            self.bus.set_filters([{"can_id": i, "can_mask": 0x7FF, "extended": False} for i in sorted(ids)])
        except (NotImplementedError, self._can.CanError, OSError):
            pass  # an interface without filters delivers everything; we sort it out

    def send(self, can_id: int, data: bytes) -> None:
        self.bus.send(self._can.Message(arbitration_id=can_id, is_extended_id=False, data=bytes(data)))

    def recv(self, timeout_s: float):
        m = self.bus.recv(max(0.0, timeout_s))
        if m is None:
            return None
        if m.is_error_frame or m.is_remote_frame or m.is_extended_id:
            return (None, b"")
        return (m.arbitration_id, bytes(m.data))

    def flush(self) -> None:
        while self.bus.recv(0) is not None:
            pass

    def close(self) -> None:
        self.bus.shutdown()


def open_bus(interface: str, channel: str, bitrate: Optional[int] = None):
    """A python-can bus, or one clear error for the usual ways this fails."""
    import logging
    need_third_party()
    import can
    logging.getLogger("can").setLevel(logging.CRITICAL)
    kwargs = {"interface": interface, "channel": channel}
    if bitrate:
        kwargs["bitrate"] = bitrate
    try:
        return can.Bus(**kwargs)
    except OSError as e:
        raise _socketcan_error(e, channel) from None
    except (can.CanError, ValueError, ImportError, NotImplementedError) as e:
        raise DtctuneError("cannot open CAN interface %s (%s): %s"
                           % (channel, interface, " ".join(str(e).split())), EXIT_NO_ANSWER) from None


def open_transport(interface: str, channel: str, bitrate: Optional[int] = None):
    """The cheapest transport for this interface: a raw socket for socketcan (unless a bit rate
    is to be set, which python-can does through netlink), else python-can."""
    if interface == "socketcan" and not bitrate:
        return SocketcanTransport(channel)
    return PythonCanTransport(open_bus(interface, channel, bitrate), channel)


# ------------------------------------------------------------------------------ the SDO lock

def lock_path(interface: str, channel: str, node_id: int) -> str:
    """The lock file of one SDO channel: $DTCTUNE_LOCK_DIR (default $TMPDIR, else /tmp)/dtctune-sdo-INTERFACE-CHANNEL-nodeN.lock."""
    # (not tempfile.gettempdir(): importing tempfile costs start-up time)
    d = os.environ.get("DTCTUNE_LOCK_DIR") or os.environ.get("TMPDIR") or "/tmp"
    safe = lambda s: "".join(c if c.isascii() and (c.isalnum() or c in "_.-") else "_" for c in str(s))  # noqa: E731
    return os.path.join(d, "dtctune-sdo-%s-%s-node%d.lock" % (safe(interface), safe(channel), node_id))


class SdoLock:
    """An advisory lock (fcntl.flock, exclusive) held around each SDO transfer, so that two
    dtctune processes on the same interface, channel and node take turns on the drive's one
    SDO server instead of mixing their requests and answers. Other programs (that do not take
    the lock) are not held back. The file is created on first use and never removed (removing
    it would let two processes lock two different files)."""

    def __init__(self, path: Optional[str], wait_s: float = LOCK_WAIT_S):
        self.path = path
        self.wait_s = wait_s
        self.fd: Optional[int] = None
        self.depth = 0
        self.waited_s = 0.0  # total time spent waiting for other processes (for tests, curiosity)

    def _open(self) -> int:
        if self.fd is None:
            try:
                self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o666)
                try:
                    os.fchmod(self.fd, 0o666)  # other users of the bus share it (umask aside)
                except OSError:
                    pass
            except OSError:
                try:  # someone else's file in a sticky /tmp: reading is enough for flock
                    self.fd = os.open(self.path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
                except OSError as e:
                    raise DtctuneError("cannot open the SDO lock file %s: %s (set DTCTUNE_LOCK_DIR to a "
                                       "writable directory)" % (self.path, e.strerror or e), EXIT_USAGE) from None
        return self.fd

    def __enter__(self):
        if self.path is None:
            return self
        if self.depth == 0:
            import fcntl
            fd = self._open()
            t0 = time.monotonic()
            delay = 0.002
            while True:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    break
                except BlockingIOError:
                    if time.monotonic() - t0 > self.wait_s:
                        raise DtctuneError(
                            "the SDO channel is busy: another dtctune has held %s for more than %.0f s"
                            % (self.path, self.wait_s), EXIT_NO_ANSWER) from None
                    time.sleep(delay)
                    delay = min(delay * 2, 0.02)
            self.waited_s += time.monotonic() - t0
        self.depth += 1
        return self

    def __exit__(self, *exc):
        if self.path is None:
            return
        self.depth -= 1
        if self.depth == 0:
            import fcntl
            fcntl.flock(self.fd, fcntl.LOCK_UN)

    def close(self) -> None:
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None


# ------------------------------------------------------------------------------ the link

class Link:
    """SDO access to node `node_id` through `bus` (a transport above, or a python-can bus),
    values decoded with the EDS `dic`."""

    def __init__(self, bus, dic: Dictionary, node_id: int, timeout_s: float = 1.0,
                 channel: str = "?", lock: Optional[SdoLock] = None):
        self.transport = bus if hasattr(bus, "set_ids") else PythonCanTransport(bus, channel)
        self.dic = dic
        self.node_id = node_id
        self.channel = channel
        self.timeout_s = timeout_s
        self.lock = lock if lock is not None else SdoLock(None)
        self.tx_id = 0x600 + node_id
        self.rx_id = 0x580 + node_id
        # Only the SDO answers reach us (telemetry has a socket of its own).
        self.transport.set_ids({self.rx_id})

    def close(self) -> None:
        try:
            self.transport.close()
        except Exception:
            pass
        self.lock.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ------------------------------------------------------------------ errors
    def _no_answer(self, what: str) -> DtctuneError:
        return DtctuneError(
            "timeout: node %d did not answer %s on %s within %.1f s (is the drive running, "
            "on this bus, with this node id?)" % (self.node_id, what, self.channel, self.timeout_s),
            EXIT_NO_ANSWER)

    def _translate(self, e: Exception, what: str) -> DtctuneError:
        if isinstance(e, SdoAbort):
            return DtctuneError("the drive refused %s: %s" % (what, abort_codes.describe(e.code)), EXIT_REFUSED)
        if isinstance(e, SdoTimeout):
            return self._no_answer(what)
        if isinstance(e, SdoProtocolError):
            return DtctuneError("SDO protocol error during %s: %s" % (what, e), EXIT_NO_ANSWER)
        if isinstance(e, OSError):
            if e.errno in (errno.ENETDOWN, errno.ENODEV):
                return _socketcan_error(e, self.channel)
            return DtctuneError("CAN error during %s: %s" % (what, e.strerror or e), EXIT_NO_ANSWER)
        return DtctuneError("CAN error during %s: %s" % (what, " ".join(str(e).split())), EXIT_NO_ANSWER)

    def _errors(self):
        errs = (SdoAbort, SdoTimeout, SdoProtocolError, OSError)
        if isinstance(self.transport, PythonCanTransport):
            errs = errs + (self.transport._can.CanError,)
        return errs

    # ------------------------------------------------------------------ SDO protocol
    def _abort(self, mux: bytes, code: int) -> None:
        try:
            self.transport.send(self.tx_id, bytes([0x80]) + mux + struct.pack("<L", code))
        except Exception:
            pass

    def _exchange(self, req: bytes, mux: bytes, initiate: bool) -> bytes:
        """Send a request and return the 8 bytes of its answer. For an initiate request, an
        answer about another object (another client's) is passed over."""
        self.transport.send(self.tx_id, req)
        deadline = time.monotonic() + self.timeout_s
        while True:
            left = deadline - time.monotonic()
            f = self.transport.recv(left) if left > 0 else None
            if f is None:
                self._abort(mux, ABORT_TIMEOUT)
                raise SdoTimeout()
            can_id, data = f
            if can_id != self.rx_id or len(data) < 1:
                continue
            data = bytes(data).ljust(8, b"\0")
            if (initiate or data[0] == 0x80) and data[1:4] != mux:
                continue  # not about our object: someone else's transfer
            if data[0] == 0x80:
                raise SdoAbort(struct.unpack_from("<L", data, 4)[0])
            return data

    def _upload(self, index: int, subindex: int) -> bytes:
        mux = struct.pack("<HB", index, subindex)
        with self.lock:
            self.transport.flush()
            resp = self._exchange(bytes([0x40]) + mux + bytes(4), mux, True)
            cmd = resp[0]
            if cmd & 0xE0 != 0x40:
                self._abort(mux, ABORT_COMMAND)
                raise SdoProtocolError("answer 0x%02X to an upload request" % cmd)
            if cmd & 0x02:  # expedited
                n = (cmd >> 2) & 3 if cmd & 0x01 else 0
                return resp[4:8 - n]
            size = struct.unpack_from("<L", resp, 4)[0] if cmd & 0x01 else None
            data = bytearray()
            toggle = 0
            while True:
                resp = self._exchange(bytes([0x60 | (toggle << 4)]) + bytes(7), mux, False)
                cmd = resp[0]
                if cmd & 0xE0 != 0x00:
                    self._abort(mux, ABORT_COMMAND)
                    raise SdoProtocolError("answer 0x%02X to an upload segment request" % cmd)
                if (cmd >> 4) & 1 != toggle:
                    self._abort(mux, ABORT_TOGGLE)
                    raise SdoProtocolError("toggle bit not alternated in an upload segment")
                data += resp[1:8 - ((cmd >> 1) & 7)]
                if cmd & 0x01:
                    break
                if len(data) > MAX_UPLOAD:
                    self._abort(mux, ABORT_MEMORY)
                    raise SdoProtocolError("upload longer than %d bytes" % MAX_UPLOAD)
                toggle ^= 1
            if size is not None and len(data) != size:
                raise SdoProtocolError("%d bytes uploaded, %d announced" % (len(data), size))
            return bytes(data)

    def _upload_block(self, index: int, subindex: int) -> bytes:
        """Block upload (CiA 301): initiate with CRC support and 127 segments per block, start,
        then per block the segments in sequence and our acknowledge of the last one in order (the
        server sends the rest again); the end frame gives the padding of the last segment and the
        CRC. A server that refuses the block protocol (0x05040001) is read segmented instead."""
        mux = struct.pack("<HB", index, subindex)
        with self.lock:
            self.transport.flush()
            try:
                resp = self._exchange(bytes([0xA4]) + mux + bytes([BLOCK_SEGMENTS, 0, 0, 0]), mux, True)
            except SdoAbort as e:
                if e.code != ABORT_COMMAND:
                    raise
                return self._upload(index, subindex)
            if resp[0] & 0xE1 != 0xC0:  # scs 6, ss 0 (initiate response)
                self._abort(mux, ABORT_COMMAND)
                raise SdoProtocolError("answer 0x%02X to a block upload request" % resp[0])
            crc_on = bool(resp[0] & 0x04)
            size = struct.unpack_from("<L", resp, 4)[0] if resp[0] & 0x02 else None
            if size is not None and size > MAX_UPLOAD:
                self._abort(mux, ABORT_MEMORY)
                raise SdoProtocolError("upload of %d bytes announced" % size)
            data = bytearray()
            self.transport.send(self.tx_id, bytes([0xA3]) + bytes(7))
            while True:
                ackseq, last = self._receive_block(mux, data)
                ack = bytes([0xA2, ackseq, BLOCK_SEGMENTS]) + bytes(5)
                if last:
                    break
                self.transport.send(self.tx_id, ack)
                if len(data) > MAX_UPLOAD:
                    self._abort(mux, ABORT_MEMORY)
                    raise SdoProtocolError("upload longer than %d bytes" % MAX_UPLOAD)
            end = self._exchange(ack, mux, False)
            if end[0] & 0xE3 != 0xC1:
                self._abort(mux, ABORT_COMMAND)
                raise SdoProtocolError("answer 0x%02X where the end of a block upload was due" % end[0])
            pad = (end[0] >> 2) & 7
            if pad:
                del data[len(data) - pad:]
            if crc_on and crc16(bytes(data)) != struct.unpack_from("<H", end, 1)[0]:
                self._abort(mux, ABORT_CRC)
                raise SdoProtocolError("CRC error in a block upload (0x%04X computed, 0x%04X sent)"
                                       % (crc16(bytes(data)), struct.unpack_from("<H", end, 1)[0]))
            self.transport.send(self.tx_id, bytes([0xA1]) + bytes(7))
            if size is not None and len(data) != size:
                raise SdoProtocolError("%d bytes uploaded, %d announced" % (len(data), size))
            return bytes(data)

    def _receive_block(self, mux: bytes, data: bytearray):
        """One block's segments, in order, appended to `data`. @return (the last seqno received
        in order, True when that segment was the last of the transfer). A segment out of order
        (one was lost) ends our acceptance: the rest of the block is passed over and the server
        sends it again after our acknowledge. A timeout after segments received in order
        acknowledges them (the server continues from there); a timeout without any ends the
        transfer."""
        ackseq = 0
        in_order = True
        deadline = time.monotonic() + self.timeout_s
        while True:
            left = deadline - time.monotonic()
            f = self.transport.recv(left) if left > 0 else None
            if f is None:
                if ackseq == 0:
                    self._abort(mux, ABORT_TIMEOUT)
                    raise SdoTimeout()
                return ackseq, False
            can_id, seg = f
            if can_id != self.rx_id or len(seg) < 1:
                continue
            seg = bytes(seg).ljust(8, b"\0")
            if seg[0] == 0x80 and seg[1:4] == mux:
                raise SdoAbort(struct.unpack_from("<L", seg, 4)[0])
            seq = seg[0] & 0x7F
            last = bool(seg[0] & 0x80)
            if in_order and seq == ackseq + 1:
                ackseq = seq
                data += seg[1:8]
                if last:
                    return ackseq, True
            else:
                in_order = False
            if last or seq >= BLOCK_SEGMENTS:
                return ackseq, False
            deadline = time.monotonic() + self.timeout_s

    def _download(self, index: int, subindex: int, data: bytes) -> None:
        mux = struct.pack("<HB", index, subindex)
        data = bytes(data)
        with self.lock:
            self.transport.flush()
            if 1 <= len(data) <= 4:
                cmd = 0x23 | ((4 - len(data)) << 2)
                resp = self._exchange(bytes([cmd]) + mux + data.ljust(4, b"\0"), mux, True)
                if resp[0] != 0x60:
                    self._abort(mux, ABORT_COMMAND)
                    raise SdoProtocolError("answer 0x%02X to a download request" % resp[0])
                return
            resp = self._exchange(bytes([0x21]) + mux + struct.pack("<L", len(data)), mux, True)
            if resp[0] != 0x60:
                self._abort(mux, ABORT_COMMAND)
                raise SdoProtocolError("answer 0x%02X to a download request" % resp[0])
            toggle = 0
            pos = 0
            while True:
                chunk = data[pos:pos + 7]
                pos += len(chunk)
                last = pos >= len(data)
                cmd = (toggle << 4) | ((7 - len(chunk)) << 1) | (1 if last else 0)
                resp = self._exchange(bytes([cmd]) + chunk.ljust(7, b"\0"), mux, False)
                if resp[0] & 0xE0 != 0x20:
                    self._abort(mux, ABORT_COMMAND)
                    raise SdoProtocolError("answer 0x%02X to a download segment" % resp[0])
                if (resp[0] >> 4) & 1 != toggle:
                    self._abort(mux, ABORT_TOGGLE)
                    raise SdoProtocolError("toggle bit not alternated in a download segment answer")
                if last:
                    return
                toggle ^= 1

    # ------------------------------------------------------------------ raw SDO
    def upload(self, index: int, subindex: int, what: str) -> bytes:
        try:
            return self._upload(index, subindex)
        except self._errors() as e:
            raise self._translate(e, what) from None

    def upload_block(self, index: int, subindex: int, what: str) -> bytes:
        """A large object by block upload (segmented if the server has no block protocol)."""
        try:
            return self._upload_block(index, subindex)
        except self._errors() as e:
            raise self._translate(e, what) from None

    def download(self, index: int, subindex: int, data: bytes, what: str) -> None:
        try:
            self._download(index, subindex, data)
        except self._errors() as e:
            raise self._translate(e, what) from None

    def abort_code_of_download(self, index: int, subindex: int, data: bytes) -> Optional[int]:
        """Write and return the drive's abort code, or None when it accepted. For tests/benchmarks."""
        try:
            self._download(index, subindex, data)
            return None
        except SdoAbort as e:
            return e.code
        except self._errors() as e:
            raise self._translate(e, "the write of 0x%04X:%d" % (index, subindex)) from None

    # ------------------------------------------------------------------ parameters
    def read(self, p: Param):
        """The raw value of a parameter (decoded by its EDS type)."""
        data = self.upload(p.index, p.subindex, "the read of %s (%s)" % (p.name, p.address))
        try:
            return p.var.decode_raw(data)
        except (struct.error, ValueError) as e:
            raise DtctuneError("%s: the drive answered %d bytes that do not decode as %s (%s)"
                               % (p.name, len(data), p.type_name, e), EXIT_NO_ANSWER) from None

    def write(self, p: Param, raw) -> None:
        try:
            data = p.var.encode_raw(raw)
        except (struct.error, ValueError, TypeError) as e:
            raise DtctuneError("%s: %r cannot be encoded as %s (%s)" % (p.name, raw, p.type_name, e)) from None
        self.download(p.index, p.subindex, data, "the write of %s = %s%s"
                      % (p.name, p.format(raw), " " + p.unit if p.unit else ""))

    def save(self) -> None:
        self.download(OBJ_STORE, 1, struct.pack("<L", SIGNATURE_SAVE), "the save (0x1010:1)")

    def restore_defaults(self) -> None:
        self.download(OBJ_RESTORE, 1, struct.pack("<L", SIGNATURE_LOAD), "the restore of defaults (0x1011:1)")

    # ------------------------------------------------------------------ NMT
    def nmt(self, state: str) -> None:
        """Send an NMT command to our node: 'OPERATIONAL', 'PRE-OPERATIONAL', 'STOPPED', 'RESET'."""
        try:
            self.transport.send(0x000, bytes([NMT_COMMANDS[state], self.node_id]))
        except self._errors() as e:
            raise DtctuneError("CAN error sending NMT %s: %s" % (state, e), EXIT_NO_ANSWER) from None
