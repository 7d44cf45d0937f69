"""Start and stop the software-in-the-loop drive (`dtc-sim --realtime --can IFACE`) for tests and
benchmarks, and wait until it answers on the bus."""
from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path
from typing import List, Optional, Sequence

import can

from .od import repo_root

SCENARIO_CHOICES = ("case1.ini", "case2.ini")


def default_sim() -> Path:
    env = os.environ.get("DTC_SIM")
    if env:
        return Path(env)
    root = Path(repo_root() or Path.cwd())
    return root / "build" / "host" / "bin" / "dtc-sim"


def default_scenario() -> Path:
    """A closed-loop (inverter-fed) scenario: $DTC_CAN_SCENARIO, else case1, else case2."""
    env = os.environ.get("DTC_CAN_SCENARIO")
    if env:
        return Path(env)
    root = Path(repo_root() or Path.cwd())
    for name in SCENARIO_CHOICES:
        p = root / "host_sim" / "scenarios" / name
        if p.is_file():
            return p
    return root / "host_sim" / "scenarios" / SCENARIO_CHOICES[0]


class Sil:
    """One dtc-sim process on a CAN interface, run until stop()."""

    def __init__(self, channel: str = "vcan0", node_id: int = 1, nvm: Optional[str] = None,
                 sim: Optional[Path] = None, scenario: Optional[Path] = None,
                 extra: Sequence[str] = (), log: Optional[str] = None):
        self.channel = channel
        self.node_id = node_id
        self.nvm = nvm
        self.sim = Path(sim) if sim else default_sim()
        self.scenario = Path(scenario) if scenario else default_scenario()
        self.extra = list(extra)
        self.log_path = log
        self.proc: Optional[subprocess.Popen] = None
        self._log = None

    def command(self) -> List[str]:
        cmd = [str(self.sim), "run", str(self.scenario), "--realtime", "--can", self.channel,
               "--duration", "inf"]
        if self.nvm:
            cmd += ["--nvm", self.nvm]
        return cmd + self.extra

    def start(self, timeout_s: float = 20.0) -> float:
        """Start and wait for the boot-up message (0x700+id, data 00). Returns seconds to boot-up."""
        if not self.sim.is_file():
            raise RuntimeError("dtc-sim not found at %s (build it: cmake --build --preset host)" % self.sim)
        if not self.scenario.is_file():
            raise RuntimeError("scenario %s not found" % self.scenario)
        bus = can.Bus(interface="socketcan", channel=self.channel,
                      can_filters=[{"can_id": 0x700 + self.node_id, "can_mask": 0x7FF}])
        try:
            self._log = open(self.log_path, "ab") if self.log_path else subprocess.DEVNULL
            t0 = time.monotonic()
            self.proc = subprocess.Popen(self.command(), stdout=self._log, stderr=subprocess.STDOUT)
            while time.monotonic() - t0 < timeout_s:
                msg = bus.recv(0.1)
                if msg is not None and bytes(msg.data[:1]) == b"\x00":
                    return time.monotonic() - t0
                if self.proc.poll() is not None:
                    raise RuntimeError("dtc-sim exited with status %d before its boot-up message (%s)"
                                       % (self.proc.returncode, " ".join(self.command())))
            raise RuntimeError("no boot-up message from node %d within %.0f s" % (self.node_id, timeout_s))
        except BaseException:
            self.stop()
            raise
        finally:
            bus.shutdown()

    def stop(self, timeout_s: float = 15.0) -> Optional[int]:
        """SIGINT (a clean stop, outputs written), then SIGKILL if it hangs. Returns the exit status."""
        rc = None
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.send_signal(signal.SIGINT)
                try:
                    self.proc.wait(timeout_s)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait()
            rc = self.proc.returncode
            self.proc = None
        if self._log not in (None, subprocess.DEVNULL):
            self._log.close()
        self._log = None
        return rc

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()
