"""Capture against a sender faster than the reader: frames must still be delivered, and a
recording window is judged by receive timestamps, including frames read after it ended."""
import threading
import time

from dtctune import telemetry


class FloodSource:
    """Never runs dry: every drain call finds max_frames frames waiting, stamped at a
    steady 3 kHz (the 1 kHz telemetry of three TPDOs) from t0 on."""

    def __init__(self, can_ids, t0):
        self.ids = list(can_ids)
        self.t0 = t0
        self.k = 0
        self.calls = 0
        self.lock = threading.Lock()

    def drain(self, out, max_frames):
        with self.lock:
            self.calls += 1
            for _ in range(max_frames):
                out.append((self.t0 + self.k / 3000.0, self.ids[self.k % len(self.ids)], bytes(8)))
                self.k += 1
        return max_frames

    def close(self):
        pass


class _Tpdo:
    def __init__(self, cob):
        self.cob_id = cob


def test_flooding_source_still_delivers_and_stops():
    t0 = 1000.0
    src = FloodSource([0x181, 0x281, 0x381], t0)
    cap = telemetry.Capture(link=None, tpdos=[_Tpdo(c) for c in (0x181, 0x281, 0x381)],
                            source_factory=lambda ids: src, poll_s=0.001)
    cap.STOP_DRAIN_S = 2.0
    cap.start()
    # An unbounded drain would never return here, and nothing would ever be seen.
    assert cap.wait_all_seen(2.0)
    # Open the window 1 s (3000 frames) ahead of the source, holding it still meanwhile,
    # so the flood cannot run past the window's start before the window is set.
    with src.lock:
        k_from = src.k + 3000
        t_from = t0 + k_from / 3000.0
        cap.window_from(t_from)
    t_until = t0 + (k_from + 2999.5) / 3000.0   # half a frame before the next one: no rounding edge
    started = time.monotonic()
    cap.stop(until=t_until)
    assert time.monotonic() - started < cap.STOP_DRAIN_S + 2.5
    ts = [f[0] for f in cap.frames]
    assert ts, "no frame in the window"
    assert min(ts) >= t_from and max(ts) < t_until
    # The backlog was read up to the end of the window: all 3000 frames of that second.
    assert len(ts) == 3000
