"""Fixtures for dtctune's unit tests: a hand-written EDS and a tiny fake drive on python-can's
in-process `virtual` bus (canopen's LocalNode as the SDO server, with range checks added)."""
from __future__ import annotations

import itertools
import struct
import threading
import time
from pathlib import Path

import can
import canopen
import pytest
from canopen.sdo.exceptions import SdoAbortedError

DATA = Path(__file__).parent / "data"
EDS = DATA / "test_drive.eds"
_channels = itertools.count()


def _eds_limits(path):
    """{(index, sub): (low, high)} straight from the EDS text (independent of the code under test)."""
    import configparser, re
    eds = configparser.RawConfigParser()
    eds.optionxform = str
    eds.read(str(path))
    out = {}
    for sec in eds.sections():
        m = re.fullmatch(r"([0-9A-Fa-f]{4})(?:sub(\d+))?", sec)
        if m and (eds.has_option(sec, "LowLimit") or eds.has_option(sec, "HighLimit")):
            lo = float(eds.get(sec, "LowLimit")) if eds.has_option(sec, "LowLimit") else None
            hi = float(eds.get(sec, "HighLimit")) if eds.has_option(sec, "HighLimit") else None
            out[(int(m.group(1), 16), int(m.group(2) or 0))] = (lo, hi)
    return out


class FakeDrive:
    """SDO server for node 1 that refuses what the real drive refuses (ranges, read-only)."""

    def __init__(self, channel: str, node_id: int = 1, eds=EDS):
        self.channel = channel
        self.network = canopen.Network()
        self.network.NOTIFIER_CYCLE = 0.05
        self.network.connect(interface="virtual", channel=channel, receive_own_messages=False)
        self.node = self.network.create_node(node_id, str(eds))
        self.limits = _eds_limits(eds)
        self.node.add_write_callback(self._on_write)
        self.writes = []      # (index, subindex, bytes) of accepted writes
        self.stored = []      # signatures written to 0x1010 / 0x1011
        self.nmt = []         # NMT commands addressed to us (or to all): 1 start, 2 stop, 0x80 pre-op
        self.on_nmt = None    # called with the command byte
        self.network.subscribe(0x000, self._on_nmt)

    def _on_nmt(self, can_id, data, timestamp):
        if len(data) >= 2 and data[1] in (0, self.node.id):
            self.nmt.append(data[0])
            if self.on_nmt:
                self.on_nmt(data[0])

    def _on_write(self, index, subindex, od, data):
        if od.data_type in (canopen.objectdictionary.REAL32,):
            value = struct.unpack("<f", data)[0]
        elif od.data_type in canopen.objectdictionary.INTEGER_TYPES:
            value = od.decode_raw(data)
        else:
            value = None
        lo, hi = self.limits.get((index, subindex), (None, None))
        if value is not None:
            if hi is not None and value > hi:
                raise SdoAbortedError(0x06090031)
            if lo is not None and value < lo:
                raise SdoAbortedError(0x06090032)
        if index in (0x1010, 0x1011):
            sig = struct.unpack("<L", data)[0]
            if sig != (0x65766173 if index == 0x1010 else 0x64616F6C):
                raise SdoAbortedError(0x08000020)
            self.stored.append((index, sig))
        self.writes.append((index, subindex, bytes(data)))

    def value(self, index, subindex=0):
        od = self.node.object_dictionary.get_variable(index, subindex)
        return od.decode_raw(self.node.get_data(index, subindex))

    def send_tpdos(self, rate_hz: float, seconds: float, start_tick: int = 0):
        """Send TPDO1 (speed, torque) and TPDO2 (vc diff in 0.1 V, tick) at rate_hz in a thread."""
        bus = can.Bus(interface="virtual", channel=self.channel)
        stop = threading.Event()

        def run():
            n = int(rate_hz * seconds)
            t0 = time.monotonic()
            for k in range(n):
                if stop.is_set():
                    break
                tick = start_tick + k
                bus.send(can.Message(arbitration_id=0x181, is_extended_id=False,
                                     data=struct.pack("<ff", 500.0 + k, -2.5)))
                bus.send(can.Message(arbitration_id=0x281, is_extended_id=False,
                                     data=struct.pack("<hI", -37, tick)))
                delay = t0 + (k + 1) / rate_hz - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
            bus.shutdown()

        th = threading.Thread(target=run, daemon=True)
        th.start()
        return th, stop

    def close(self):
        self.network.disconnect()


@pytest.fixture
def channel():
    return "dtctune-test-%d" % next(_channels)


@pytest.fixture
def drive(channel):
    d = FakeDrive(channel)
    yield d
    d.close()


@pytest.fixture
def run(channel, capsys):
    """Run the CLI in-process against the fake drive's channel; returns (status, stdout, stderr)."""
    from dtctune.cli import main

    def _run(*argv, eds=EDS, use_channel=True):
        base = ["--interface", "virtual", "--timeout", "0.3"]
        if use_channel:
            base += ["--channel", channel]
        if eds is not None:
            base += ["--eds", str(eds)]
        status = main(base + list(argv))
        cap = capsys.readouterr()
        return status, cap.out, cap.err

    return _run


@pytest.fixture(autouse=True)
def _lock_dir(tmp_path, monkeypatch):
    """The SDO lock files of the tests go to the test's own directory, not /tmp."""
    monkeypatch.setenv("DTCTUNE_LOCK_DIR", str(tmp_path))
