#!/usr/bin/env python3
"""Benchmarks of dtctune against the SIL over SocketCAN: the scope upload and the start-up of a
dtctune command. Figures only (a benchmark, never a test).

  tests/can/uml/run_in_uml.sh -- .venv/bin/python tools/dtctune_bench.py scope     # inside UML
  tests/can/uml/run_in_uml.sh -- .venv/bin/python tools/dtctune_bench.py startup
  .venv/bin/python tools/dtctune_bench.py --channel vcan0 scope                    # a host with vcan0

It starts the SIL itself (build/host/bin/dtc-sim --realtime --can CHANNEL, closed loop, as
tools/can_bench.py does) and stops it at the end.

  scope    arms the drive's scope on 4 channels (a manual trigger), waits for the capture, then
           uploads the 16 KiB capture N times by each method, alternating: segmented (CiA 301
           segmented upload: one request per 7 bytes, what dtctune did before) and block
           (CiA 301 block upload: 127 segments per acknowledge, CRC-checked, what `dtctune scope`
           does now). Both go through dtctune's own SDO client; the bytes must be equal.
  startup  times whole dtctune processes, each a new interpreter, N runs each, alternating:
           `python -c pass` (the interpreter alone), `python -S -c pass` (without the site
           module), `dtctune --help` and `dtctune get PARAM` against the SIL (EDS read, socket,
           one SDO upload), as `python -m dtctune` and as the venv's `dtctune` (the launcher
           tools/setup_venv.sh writes: python -S, the quick command-line path). Also the import time of each module dtctune's get path loads
           (python -X importtime, one run) and the EDS read alone.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # the dtctune package next to this script, installed or not

from dtctune.link import Link, SdoLock, lock_path, open_transport  # noqa: E402
from dtctune.od import Dictionary, find_eds  # noqa: E402
from dtctune.scope import resolve_channels  # noqa: E402
from dtctune.sil import Sil  # noqa: E402


def stats(vals):
    s = sorted(vals)
    return "median %7.1f ms  min %7.1f ms  max %7.1f ms  (n=%d)" % (
        1e3 * statistics.median(s), 1e3 * s[0], 1e3 * s[-1], len(s))


def start_sil(args):
    nvm = tempfile.NamedTemporaryFile(prefix="dtctune_bench_", suffix=".nvm", delete=False).name
    os.unlink(nvm)
    sil = Sil(args.channel, args.node, nvm=nvm, sim=args.sim)
    boot = sil.start(timeout_s=30.0)
    print("SIL: %s (boot-up after %.2f s)" % (" ".join(sil.command()), boot))
    return sil


def bench_scope(args, dic, link) -> None:
    p = dic.lookup
    link.write(p("scope_command"), 0)
    chans = resolve_channels(dic, "speed_ref_rpm,speed_est_rpm,te_ref_Nm,ia_A")  # the README's
    for i, sig in enumerate(chans):
        link.write(p("scope_channel_%d" % (i + 1)), sig.subindex)
    link.write(p("scope_trigger"), 0)
    link.write(p("scope_command"), 1)
    time.sleep(0.5)
    link.write(p("scope_command"), 2)  # manual trigger
    t_end = time.monotonic() + 30.0
    while int(link.read(p("scope_state"))) != 3:
        if time.monotonic() > t_end:
            raise RuntimeError("no scope capture within 30 s")
        time.sleep(0.05)
    pd = p("scope_data")
    times = {"segmented": [], "block": []}
    ref = None
    for _ in range(args.n):
        for method in ("segmented", "block"):
            t0 = time.perf_counter()
            if method == "segmented":
                data = link.upload(pd.index, pd.subindex, "segmented upload")
            else:
                data = link.upload_block(pd.index, pd.subindex, "block upload")
            times[method].append(time.perf_counter() - t0)
            if ref is None:
                ref = data
            elif data != ref:
                raise RuntimeError("the %s upload gave other bytes than the first upload" % method)
    print("scope upload of %d bytes (%s), %d x each, alternating:" % (len(ref), args.channel, args.n))
    for method, vals in times.items():
        med = statistics.median(vals)
        print("  %-9s: %s  %6.1f KiB/s" % (method, stats(vals), len(ref) / med / 1024.0))
    print("  block / segmented (medians): %.2f" % (statistics.median(times["block"]) /
                                                    statistics.median(times["segmented"])))


def run_timed(cmd, env):
    t0 = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    dt = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), r.returncode, r.stderr.decode()[-400:]))
    return dt


def bench_startup(args, eds: str) -> None:
    py = sys.executable
    env = dict(os.environ)
    env["PYTHONPATH"] = str(HERE) + os.pathsep + env.get("PYTHONPATH", "")
    common = ["--interface", "socketcan", "--channel", args.channel, "--node", str(args.node), "--eds", eds]
    cmds = {
        "python -c pass": [py, "-c", "pass"],
        "python -S -c pass": [py, "-S", "-c", "pass"],
        "python -m dtctune --help": [py, "-m", "dtctune", "--help"],
        "python -m dtctune get": [py, "-m", "dtctune"] + common + ["get", args.param],
    }
    script = Path(py).parent / "dtctune"  # the launcher tools/setup_venv.sh writes (what users run)
    if script.is_file():
        cmds["dtctune --help"] = [str(script), "--help"]
        cmds["dtctune get"] = [str(script)] + common + ["get", args.param]
    times = {k: [] for k in cmds}
    for _ in range(args.n):
        for k, cmd in cmds.items():
            times[k].append(run_timed(cmd, env))
    print("start-up, whole processes (%s), %d x each, alternating:" % (py, args.n))
    for k, vals in times.items():
        print("  %-28s %s" % (k, stats(vals)))
    # Where a get spends its time: the heaviest imports (cumulative, one run) and the EDS read.
    how = [py, "-S", "-X", "importtime", str(script)] if script.is_file() else [py, "-X", "importtime", "-m", "dtctune"]
    r = subprocess.run(how + common + ["get", args.param], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    rows = []
    for line in r.stderr.decode().splitlines():
        if line.startswith("import time:") and "|" in line:
            parts = line[len("import time:"):].split("|")
            if parts[1].strip().isdigit():
                rows.append((int(parts[1]), parts[2][1:]))  # the name, indented 2 per level
    top = [x for x in rows if not x[1].startswith(" ")]
    top.sort(reverse=True)
    print("  heaviest top-level imports of `get` (%s, python -X importtime, cumulative, one run):"
          % ("the launcher" if script.is_file() else "python -m dtctune"))
    for us, name in top[:8]:
        print("    %8.1f ms  %s" % (us / 1e3, name.strip()))
    t0 = time.perf_counter()
    Dictionary(eds, args.node)
    print("  EDS read (dtctune.od.Dictionary, in this process): %.1f ms" % (1e3 * (time.perf_counter() - t0)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=("scope", "startup"))
    ap.add_argument("--channel", default="vcan0")
    ap.add_argument("--node", type=int, default=1)
    ap.add_argument("--eds", default=None)
    ap.add_argument("--sim", default=None, help="dtc-sim binary (default build/host/bin/dtc-sim)")
    ap.add_argument("-n", type=int, default=None, help="runs of each (default: scope 5, startup 10)")
    ap.add_argument("--param", default="rbfn_gamma_w", help="parameter `get` reads (startup)")
    args = ap.parse_args(argv)
    if args.n is None:
        args.n = 5 if args.what == "scope" else 10
    eds = str(find_eds(args.eds))
    dic = Dictionary(eds, args.node)
    sil = start_sil(args)
    try:
        if args.what == "scope":
            lock = SdoLock(lock_path("socketcan", args.channel, args.node))
            with Link(open_transport("socketcan", args.channel), dic, args.node, 2.0, args.channel,
                      lock=lock) as link:
                bench_scope(args, dic, link)
        else:
            bench_startup(args, eds)
    except RuntimeError as e:
        print("dtctune_bench: error: %s" % e, file=sys.stderr)
        return 1
    finally:
        sil.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
