"""dtctune's own SDO client against scripted (and hostile) servers on python-can's virtual bus:
segmented transfers, answers about other objects, toggle errors, endless uploads."""
import itertools
import struct
import threading

import can
import pytest

from dtctune import link as link_mod
from dtctune.errors import DtctuneError, EXIT_NO_ANSWER
from dtctune.link import Link
from dtctune.od import Dictionary

from conftest import EDS

_n = itertools.count()
MUX = struct.pack("<HB", 0x1008, 0)   # Manufacturer device name (VISIBLE_STRING) in the test EDS


class Server:
    """Answers requests to node 1 with script(request) -> list of answers (8-byte payloads)."""

    def __init__(self, channel, script):
        self.bus = can.Bus(interface="virtual", channel=channel)
        self.script = script
        self.requests = []
        self.stop = threading.Event()
        self.th = threading.Thread(target=self.run, daemon=True)
        self.th.start()

    def run(self):
        while not self.stop.is_set():
            m = self.bus.recv(0.02)
            if m is None or m.arbitration_id != 0x601:
                continue
            req = bytes(m.data)
            self.requests.append(req)
            for ans in self.script(req, len(self.requests)):
                self.bus.send(can.Message(arbitration_id=0x581, is_extended_id=False, data=ans))

    def close(self):
        self.stop.set()
        self.th.join()
        self.bus.shutdown()


@pytest.fixture
def setup():
    made = []

    def _make(script):
        ch = "sdo-test-%d" % next(_n)
        srv = Server(ch, script)
        lk = Link(can.Bus(interface="virtual", channel=ch), Dictionary(EDS, 1), 1, timeout_s=0.3, channel=ch)
        made.append((srv, lk))
        return srv, lk

    yield _make
    for srv, lk in made:
        lk.close()
        srv.close()


def last_abort(srv):
    """The client's abort request, once the server thread has it (it is sent just before the error)."""
    import time
    t_end = time.monotonic() + 2.0
    while time.monotonic() < t_end:
        aborts = [r for r in srv.requests if r[0] == 0x80]
        if aborts:
            return aborts[-1]
        time.sleep(0.01)
    raise AssertionError("no abort sent: %r" % srv.requests)


def segments(data: bytes, toggles=None):
    out = []
    chunks = [data[i:i + 7] for i in range(0, len(data), 7)] or [b""]
    for k, c in enumerate(chunks):
        t = (k % 2) if toggles is None else toggles[k]
        last = k == len(chunks) - 1
        out.append(bytes([(t << 4) | ((7 - len(c)) << 1) | (1 if last else 0)]) + c.ljust(7, b"\0"))
    return out


def test_segmented_upload(setup):
    text = b"a drive of twenty b."
    segs = segments(text)

    def script(req, n):
        if req[0] == 0x40:
            return [bytes([0x41]) + req[1:4] + struct.pack("<L", len(text))]
        return [segs[n - 2]]

    srv, lk = setup(script)
    assert lk.upload(0x1008, 0, "x") == text
    assert [r[0] for r in srv.requests] == [0x40, 0x60, 0x70, 0x60]


def test_answer_about_another_object_is_passed_over(setup):
    def script(req, n):
        other = bytes([0x4F, 0x00, 0x26, 0x09, 7, 0, 0, 0])       # someone else's answer
        mine = bytes([0x4F]) + req[1:4] + bytes([42, 0, 0, 0])
        return [other, mine]

    srv, lk = setup(script)
    assert lk.upload(0x1001, 0, "x") == bytes([42])


def test_only_foreign_answers_is_a_timeout_and_aborts(setup):
    def script(req, n):
        if req[0] == 0x80:
            return []
        return [bytes([0x4F, 0x00, 0x26, 0x09, 7, 0, 0, 0])]

    srv, lk = setup(script)
    with pytest.raises(DtctuneError) as e:
        lk.upload(0x1001, 0, "the read of x")
    assert e.value.status == EXIT_NO_ANSWER and "timeout" in str(e.value)
    abort = last_abort(srv)
    assert abort[1:4] == struct.pack("<HB", 0x1001, 0)
    assert struct.unpack_from("<L", abort, 4)[0] == 0x05040000


def test_toggle_error_is_reported_and_aborted(setup):
    segs = segments(b"0123456789abcdef", toggles=[0, 0, 0])

    def script(req, n):
        if req[0] == 0x40:
            return [bytes([0x41]) + req[1:4] + struct.pack("<L", 16)]
        if req[0] == 0x80:
            return []
        return [segs[min(n - 2, 2)]]

    srv, lk = setup(script)
    with pytest.raises(DtctuneError, match="toggle"):
        lk.upload(0x1008, 0, "x")
    assert struct.unpack_from("<L", last_abort(srv), 4)[0] == 0x05030000


def test_endless_upload_is_cut_off(setup, monkeypatch):
    monkeypatch.setattr(link_mod, "MAX_UPLOAD", 200)

    def script(req, n):
        if req[0] == 0x40:
            return [bytes([0x40]) + req[1:4] + bytes(4)]          # segmented, size not indicated
        if req[0] == 0x80:
            return []
        return [bytes([req[0] & 0x10]) + b"xxxxxxx"]               # never the last segment

    srv, lk = setup(script)
    with pytest.raises(DtctuneError, match="longer than 200 bytes"):
        lk.upload(0x1008, 0, "x")
    assert len(srv.requests) < 60


def test_size_mismatch_is_an_error(setup):
    segs = segments(b"short")

    def script(req, n):
        if req[0] == 0x40:
            return [bytes([0x41]) + req[1:4] + struct.pack("<L", 99)]
        return [segs[0]]

    srv, lk = setup(script)
    with pytest.raises(DtctuneError, match="5 bytes uploaded, 99 announced"):
        lk.upload(0x1008, 0, "x")


def test_segmented_download(setup):
    got = bytearray()

    def script(req, n):
        if req[0] == 0x21:
            assert struct.unpack_from("<L", req, 4)[0] == 10
            return [bytes([0x60]) + req[1:4] + bytes(4)]
        n_unused = (req[0] >> 1) & 7
        got.extend(req[1:8 - n_unused])
        return [bytes([0x20 | (req[0] & 0x10)]) + bytes(7)]

    srv, lk = setup(script)
    lk.download(0x1008, 0, b"0123456789", "x")
    assert bytes(got) == b"0123456789"
    assert [r[0] for r in srv.requests] == [0x21, 0x00, 0x19]  # 7 bytes; toggled, 4 unused, last


def test_short_and_garbage_frames_do_not_crash(setup):
    def script(req, n):
        return [b"", b"\x4f", bytes([0x4F]) + req[1:4] + b"\x05"]

    srv, lk = setup(script)
    assert lk.upload(0x1001, 0, "x") == bytes([5])


# ------------------------------------------------------------------ block upload

def crc_xmodem(data: bytes) -> int:
    """CRC-16/XMODEM, table-driven (independent of link.crc16); check value 0x31C3."""
    table = []
    for i in range(256):
        r = i << 8
        for _ in range(8):
            r = ((r << 1) ^ 0x1021) & 0xFFFF if r & 0x8000 else (r << 1) & 0xFFFF
        table.append(r)
    crc = 0
    for b in data:
        crc = ((crc << 8) & 0xFFFF) ^ table[((crc >> 8) ^ b) & 0xFF]
    return crc


def test_crc16_check_value():
    assert link_mod.crc16(b"123456789") == 0x31C3
    assert crc_xmodem(b"123456789") == 0x31C3


class BlockServer:
    """A CiA 301 block upload server for `data` as a script: blocks as the client asks, the
    segments in `drop` (a set of (block number, seqno)) never sent, an optional wrong CRC."""

    def __init__(self, data: bytes, drop=(), bad_crc=False):
        self.data, self.drop, self.bad_crc = data, set(drop), bad_crc
        self.pos = 0
        self.block = 0
        self.blksize = 0
        self.acks = []

    def _send_block(self):
        out = []
        for seq in range(1, self.blksize + 1):
            at = self.pos + 7 * (seq - 1)
            chunk = self.data[at:at + 7]
            last = at + 7 >= len(self.data)
            if (self.block, seq) not in self.drop:
                out.append(bytes([seq | (0x80 if last else 0)]) + chunk.ljust(7, b"\0"))
            if last:
                self.last_seq = seq
                break
        else:
            self.last_seq = 0
        return out

    def __call__(self, req, n):
        cmd = req[0]
        if cmd & 0xE3 == 0xA0:  # initiate
            self.blksize = req[4]
            return [bytes([0xC6]) + req[1:4] + struct.pack("<L", len(self.data))]
        if cmd == 0xA3:
            return self._send_block()
        if cmd == 0xA2:
            ackseq, self.blksize = req[1], req[2]
            self.acks.append(ackseq)
            done = self.last_seq and ackseq >= self.last_seq
            self.pos += 7 * ackseq
            if done:
                pad = self.pos - len(self.data)
                crc = crc_xmodem(self.data) ^ (1 if self.bad_crc else 0)
                return [bytes([0xC1 | (pad << 2)]) + struct.pack("<H", crc) + bytes(5)]
            self.block += 1
            return self._send_block()
        return []


def test_block_upload_of_several_blocks_with_crc(setup):
    data = bytes((i * 13 + 5) & 0xFF for i in range(2000))  # 286 segments: blocks 127, 127, 32
    srv_script = BlockServer(data)
    srv, lk = setup(srv_script)
    assert lk.upload_block(0x1008, 0, "x") == data
    assert srv_script.acks == [127, 127, 32]
    import time
    t_end = time.monotonic() + 2.0
    while srv.requests[-1][0] != 0xA1 and time.monotonic() < t_end:
        time.sleep(0.01)
    assert srv.requests[-1][0] == 0xA1  # the end response


def test_block_upload_lost_segment_is_acknowledged_short_and_sent_again(setup):
    data = bytes(range(256)) * 4
    srv_script = BlockServer(data, drop={(0, 50)})
    srv, lk = setup(srv_script)
    assert lk.upload_block(0x1008, 0, "x") == data
    assert srv_script.acks[0] == 49, "only the segments in order are acknowledged"


def test_block_upload_crc_error_aborts(setup):
    srv, lk = setup(BlockServer(b"hello block upload", bad_crc=True))
    with pytest.raises(DtctuneError, match="CRC error"):
        lk.upload_block(0x1008, 0, "x")
    assert struct.unpack_from("<L", last_abort(srv), 4)[0] == 0x05040004


def test_block_upload_falls_back_to_segmented_when_refused(setup):
    text = b"DTC3L-RBFN segmented fallback"

    def script(req, n):
        if req[0] & 0xE0 == 0xA0:
            return [bytes([0x80]) + req[1:4] + struct.pack("<L", 0x05040001)]
        if req[0] == 0x40:
            return [bytes([0x41]) + req[1:4] + struct.pack("<L", len(text))]
        k = sum(1 for r in srv.requests if r[0] & 0xE0 == 0x60) - 1
        return [segments(text)[k]]

    srv, lk = setup(script)
    assert lk.upload_block(0x1008, 0, "x") == text
