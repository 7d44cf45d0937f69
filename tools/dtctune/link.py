"""The CAN link to one drive: a python-can bus, a canopen network, SDO access with plain errors."""
from __future__ import annotations

import errno
import logging
import struct
from typing import Optional

import can
import canopen
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

from . import abort_codes
from .errors import DtctuneError, EXIT_NO_ANSWER, EXIT_REFUSED
from .od import Dictionary, Param

# CiA 301 signatures for store (0x1010) and restore (0x1011): "save" and "load" in ASCII,
# sent as UNSIGNED32 little-endian.
SIGNATURE_SAVE = 0x65766173
SIGNATURE_LOAD = 0x64616F6C
OBJ_STORE = 0x1010
OBJ_RESTORE = 0x1011


def open_bus(interface: str, channel: str, bitrate: Optional[int] = None) -> can.BusABC:
    """A python-can bus, or one clear error for the usual ways this fails."""
    logging.getLogger("can").setLevel(logging.CRITICAL)
    kwargs = {"interface": interface, "channel": channel}
    if bitrate:
        kwargs["bitrate"] = bitrate
    try:
        return can.Bus(**kwargs)
    except OSError as e:
        if e.errno == errno.EAFNOSUPPORT:
            raise DtctuneError("SocketCAN is not available in this kernel (errno 97); use a kernel "
                               "with CAN/vcan, or run inside tests/can/uml/run_in_uml.sh",
                               EXIT_NO_ANSWER) from None
        if e.errno == errno.ENODEV:
            raise DtctuneError("CAN interface %s does not exist (create it: ip link add dev %s type vcan; "
                               "ip link set up %s)" % (channel, channel, channel), EXIT_NO_ANSWER) from None
        if e.errno == errno.ENETDOWN:
            raise DtctuneError("CAN interface %s is down (ip link set up %s)" % (channel, channel),
                               EXIT_NO_ANSWER) from None
        raise DtctuneError("cannot open CAN interface %s (%s): %s" % (channel, interface, e),
                           EXIT_NO_ANSWER) from None
    except (can.CanError, ValueError, ImportError, NotImplementedError) as e:
        raise DtctuneError("cannot open CAN interface %s (%s): %s"
                           % (channel, interface, " ".join(str(e).split())), EXIT_NO_ANSWER) from None


class Link:
    """SDO access to node `node_id` through `bus`, values decoded with the EDS `dic`."""

    def __init__(self, bus: can.BusABC, dic: Dictionary, node_id: int, timeout_s: float = 1.0,
                 channel: str = "?"):
        self.bus = bus
        self.dic = dic
        self.node_id = node_id
        self.channel = channel
        self.timeout_s = timeout_s
        self.network = canopen.Network(bus)
        # The receive thread polls with this period; closing waits for it, so keep it short.
        self.network.NOTIFIER_CYCLE = 0.05
        self.network.connect()  # starts the receive thread on the existing bus
        self.node = canopen.RemoteNode(node_id, dic.od)
        self.network.add_node(self.node)
        self.node.sdo.RESPONSE_TIMEOUT = timeout_s
        # Only what we use reaches Python: on a busy bus (telemetry at kHz rates) the receive
        # thread would otherwise spend its time on frames nobody reads.
        self._ids = {0x580 + node_id}
        self._apply_filters()
        # One attempt: a drive that does not answer in timeout_s is reported, not retried.
        self.node.sdo.MAX_RETRIES = 1

    def listen(self, can_ids) -> None:
        """Also receive these identifiers (e.g. TPDOs) from now on."""
        self._ids.update(can_ids)
        self._apply_filters()

    def _apply_filters(self) -> None:
        try:
            self.bus.set_filters([{"can_id": i, "can_mask": 0x7FF, "extended": False} for i in sorted(self._ids)])
        except (NotImplementedError, can.CanError, OSError):
            pass  # an interface without filters delivers everything; canopen sorts it out

    def close(self) -> None:
        try:
            self.network.disconnect()  # stops the notifier and shuts the bus down
        except Exception:
            pass

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
        if isinstance(e, SdoAbortedError):
            return DtctuneError("the drive refused %s: %s" % (what, abort_codes.describe(e.code)),
                                EXIT_REFUSED)
        if isinstance(e, SdoCommunicationError):
            if "No SDO response" in str(e):
                return self._no_answer(what)
            return DtctuneError("SDO protocol error during %s: %s" % (what, e), EXIT_NO_ANSWER)
        if isinstance(e, can.CanError) or isinstance(e, OSError):
            return DtctuneError("CAN error during %s: %s" % (what, " ".join(str(e).split())),
                                EXIT_NO_ANSWER)
        raise e

    # ------------------------------------------------------------------ raw SDO
    def upload(self, index: int, subindex: int, what: str) -> bytes:
        try:
            return self.node.sdo.upload(index, subindex)
        except (SdoAbortedError, SdoCommunicationError, can.CanError, OSError) as e:
            raise self._translate(e, what) from None

    def download(self, index: int, subindex: int, data: bytes, what: str) -> None:
        try:
            self.node.sdo.download(index, subindex, data)
        except (SdoAbortedError, SdoCommunicationError, can.CanError, OSError) as e:
            raise self._translate(e, what) from None

    def abort_code_of_download(self, index: int, subindex: int, data: bytes) -> Optional[int]:
        """Write and return the drive's abort code, or None when it accepted. For tests/benchmarks."""
        try:
            self.node.sdo.download(index, subindex, data)
            return None
        except SdoAbortedError as e:
            return e.code
        except (SdoCommunicationError, can.CanError, OSError) as e:
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
            self.node.nmt.state = state
        except (can.CanError, OSError) as e:
            raise DtctuneError("CAN error sending NMT %s: %s" % (state, e), EXIT_NO_ANSWER) from None
