"""The SDO lock (issue 12): two dtctune processes on one bus and node take turns on the drive's
single SDO channel. Checked with real processes and a shared log of their transfers: with the
lock no transfer overlaps another; the same run without it does overlap (so the check can fail)."""
import os
import subprocess
import sys
import textwrap

import pytest

from dtctune.link import SdoLock, lock_path

WORKER = textwrap.dedent("""
    import os, sys, time
    from dtctune.link import SdoLock
    path, log, n, use_lock = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4] == "1"
    lock = SdoLock(path if use_lock else None)
    fd = os.open(log, os.O_WRONLY | os.O_APPEND)
    for k in range(n):
        with lock:  # one "transfer": begin, some time on the bus, end
            os.write(fd, b"B%d\\n" % os.getpid())
            time.sleep(0.002)
            os.write(fd, b"E%d\\n" % os.getpid())
    print("done")
""")


def _run_pair(tmp_path, use_lock: bool):
    log = tmp_path / ("log-%d" % use_lock)
    log.write_text("")
    path = str(tmp_path / "sdo.lock")
    procs = [subprocess.Popen([sys.executable, "-c", WORKER, path, str(log), "60", "1" if use_lock else "0"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [p.communicate(timeout=120) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], results
    assert all(r[0].strip() == "done" for r in results)
    lines = log.read_text().split()
    assert len(lines) == 2 * 2 * 60
    # overlapping transfers: a begin while another process's transfer is open
    overlaps, open_pid = 0, None
    for line in lines:
        kind, pid = line[0], line[1:]
        if kind == "B":
            if open_pid is not None and open_pid != pid:
                overlaps += 1
            open_pid = pid
        else:
            open_pid = None if open_pid == pid else open_pid
    return overlaps


def test_two_processes_take_turns_with_the_lock(tmp_path):
    assert _run_pair(tmp_path, use_lock=True) == 0


def test_without_the_lock_they_collide(tmp_path):
    # the control experiment: the same workers without the lock overlap
    assert _run_pair(tmp_path, use_lock=False) > 0


def test_lock_path_per_interface_channel_node(monkeypatch, tmp_path):
    monkeypatch.setenv("DTCTUNE_LOCK_DIR", str(tmp_path))
    a = lock_path("socketcan", "vcan0", 1)
    assert a == str(tmp_path / "dtctune-sdo-socketcan-vcan0-node1.lock")
    assert len({a, lock_path("socketcan", "vcan1", 1), lock_path("socketcan", "vcan0", 2),
                lock_path("virtual", "vcan0", 1)}) == 4
    assert "/" not in os.path.basename(lock_path("socketcan", "a/../b", 1))


def test_busy_lock_times_out_with_one_clear_error(tmp_path):
    import fcntl
    from dtctune.errors import DtctuneError, EXIT_NO_ANSWER
    path = str(tmp_path / "held.lock")
    holder = os.open(path, os.O_RDWR | os.O_CREAT)
    fcntl.flock(holder, fcntl.LOCK_EX)
    try:
        with pytest.raises(DtctuneError) as e:
            with SdoLock(path, wait_s=0.2):
                pass
        assert e.value.status == EXIT_NO_ANSWER and "busy" in str(e.value)
    finally:
        os.close(holder)
    with SdoLock(path, wait_s=0.2) as lk:  # free again
        assert lk.depth == 1
