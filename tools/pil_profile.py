#!/usr/bin/env python3
"""Where the control interrupt's instructions go, per function.

Replays the first TICKS ticks of one PIL recording (dtc-sim run ... --record-samples)
on dtc-pil.elf under QEMU with one instruction per translation block and the
execution log on (-singlestep -d exec,nochain), follows the log through a FIFO,
and counts every instruction executed inside the tick interrupt
(hal_pil_tick_irq until the return to measure_irq), per symbol of the ELF
(functions the compiler inlined count in their caller). Ticks before FROM are
not counted (the magnetising phase comes first in every recording).

  tools/pil_profile.py REC [--ticks N] [--from K] [--elf ELF] [--annotate SYMBOL ...]

Prints instructions per tick per function, largest first, and the total per
tick (compare with tools/pil_bench.sh's figure for the same ticks: the
exception entry and return are not instructions and are not in the log, so the
total here is the bench's less nothing but the calibration handler's share).
--annotate prints the disassembly of SYMBOL with the executions per tick of
each instruction. A profiling aid, not a benchmark: slow (~1 s per 100 ticks).
"""
import argparse
import bisect
import collections
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HEADER_BYTES = 96
RECORD_BYTES = 124
ISR_ENTRY = "hal_pil_tick_irq"
ISR_CALLER = "measure_irq"


def symbols(elf: Path):
    out = subprocess.run(["arm-none-eabi-nm", "-S", "--defined-only", str(elf)], check=True,
                         capture_output=True, text=True).stdout
    syms = []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tTwW":
            syms.append((int(parts[0], 16) & ~1, int(parts[1], 16), parts[3]))
    syms.sort()
    return syms


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rec")
    ap.add_argument("--ticks", type=int, default=3000)
    ap.add_argument("--from", dest="start", type=int, default=0)
    ap.add_argument("--elf", default=str(ROOT / "build/stm32g4/dtc-pil.elf"))
    ap.add_argument("--annotate", nargs="*", default=[])
    ap.add_argument("--inlined", action="store_true",
                    help="also attribute to the innermost (inlined) function and source line; needs an ELF built with -g")
    ap.add_argument("--by-file", action="store_true",
                    help="also attribute to the source file (.c) of the innermost frame not in a header; ELF with -g")
    ap.add_argument("--top", type=int, default=60, help="rows of the --inlined tables (default 60)")
    a = ap.parse_args()

    data = Path(a.rec).read_bytes()
    cfg_words = struct.unpack_from("<I", data, 8 + 12)[0]
    body = HEADER_BYTES + 4 * cfg_words
    n = min(a.ticks, (len(data) - body) // RECORD_BYTES)
    if n <= a.start:
        print(f"{a.rec}: only {n} ticks", file=sys.stderr)
        return 2
    syms = symbols(Path(a.elf))
    starts = [s[0] for s in syms]

    with tempfile.TemporaryDirectory() as tmp:
        rec = Path(tmp) / "profile.rec"
        rec.write_bytes(data[:body + n * RECORD_BYTES])
        fifo = Path(tmp) / "exec.fifo"
        os.mkfifo(fifo)
        qemu = subprocess.Popen(
            ["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
             "-semihosting-config", f"enable=on,target=native,arg=dtc-pil,arg={rec}",
             "-icount", "shift=7", "-singlestep", "-d", "exec,nochain", "-D", str(fifo), "-kernel", a.elf],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        pcs = collections.Counter()
        entries = 0
        inside = False
        with open(fifo, "r") as log:
            for line in log:
                if not line.startswith("Trace"):
                    continue
                sym = line[line.rfind("]") + 2:-1]
                if sym == ISR_ENTRY and not inside:
                    inside = True
                    entries += 1
                elif sym == ISR_CALLER and inside:
                    inside = False
                if inside and entries > 2 + a.start:  # two calibration interrupts first
                    pc = int(line[line.index("[") + 1:].split("/")[1], 16)
                    pcs[pc] += 1
        out = qemu.communicate()[0]
    ticks = entries - 2 - a.start
    if qemu.returncode != 0 or ticks <= 0:
        print(out, file=sys.stderr)
        return 1
    per_sym = collections.Counter()
    for pc, c in pcs.items():
        i = bisect.bisect_right(starts, pc) - 1
        per_sym[syms[i][2] if i >= 0 and pc < syms[i][0] + max(syms[i][1], 1) else f"?{pc:08x}"] += c
    total = sum(per_sym.values())
    print(f"{Path(a.rec).name}: ticks {a.start}..{n - 1} ({ticks} interrupts), {total / ticks:.1f} instructions per tick")
    print("| function | instructions per tick | share |")
    print("|---|---:|---:|")
    for name, c in per_sym.most_common():
        print(f"| {name} | {c / ticks:.1f} | {100.0 * c / total:.1f} % |")
    if a.inlined:
        addrs = sorted(pcs)
        out = subprocess.run(["arm-none-eabi-addr2line", "-f", "-e", a.elf] + [f"{pc:x}" for pc in addrs],
                             check=True, capture_output=True, text=True).stdout.splitlines()
        by_fn = collections.Counter()
        by_line = collections.Counter()
        for k, pc in enumerate(addrs):
            fn, loc = out[2 * k], out[2 * k + 1]
            by_fn[fn] += pcs[pc]
            by_line[f"{fn} {loc.split('/')[-1]}"] += pcs[pc]
        print("\n| innermost function (inlined included) | instructions per tick |\n|---|---:|")
        for name, c in by_fn.most_common(a.top):
            print(f"| {name} | {c / ticks:.1f} |")
        print("\n| source line | instructions per tick |\n|---|---:|")
        for name, c in by_line.most_common(a.top):
            print(f"| {name} | {c / ticks:.1f} |")
    if a.by_file:
        addrs = sorted(pcs)
        out = subprocess.run(["arm-none-eabi-addr2line", "-a", "-i", "-f", "-e", a.elf] + [f"{pc:x}" for pc in addrs],
                             check=True, capture_output=True, text=True).stdout.splitlines()
        by_file = collections.Counter()
        k = -1
        chosen = {}
        frames = []
        for line in out + ["0xffffffff"]:
            if line.startswith("0x"):
                if k >= 0:
                    srcs = [f for f in frames if f.endswith(".c")]
                    chosen[addrs[k]] = (srcs[0] if srcs else (frames[0] if frames else "?"))
                k += 1
                frames = []
            elif ":" in line:
                frames.append(line.split(":")[0].split("/")[-1])
        for pc, f in chosen.items():
            by_file[f] += pcs[pc]
        print("\n| source file (inlined code counted where it is written) | instructions per tick |\n|---|---:|")
        for name, c in by_file.most_common():
            print(f"| {name} | {c / ticks:.1f} |")
    for name in a.annotate:
        match = [s for s in syms if s[2] == name]
        if not match:
            print(f"{name}: no such symbol", file=sys.stderr)
            continue
        lo, size, _ = match[0]
        dis = subprocess.run(["arm-none-eabi-objdump", "-d", "--no-show-raw-insn",
                              f"--start-address={lo}", f"--stop-address={lo + size}", a.elf],
                             check=True, capture_output=True, text=True).stdout
        print(f"\n{name}: executions per tick")
        for line in dis.splitlines():
            head = line.strip().split(":")[0]
            try:
                pc = int(head, 16)
            except ValueError:
                continue
            print(f"{pcs.get(pc, 0) / ticks:8.2f} {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
