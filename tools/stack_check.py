#!/usr/bin/env python3
"""Worst-case stack of the target image, interrupts nesting, against the reserve.

Reads the per-function frames and the call graph that GCC writes with
-fcallgraph-info=su (OBJ.ci next to every object of the stm32g4 build; the
frame sizes are those of -fstack-usage), and computes:

  * the deepest chain of every root: the background (Reset_Handler -> main ->
    drive_background ...) and every interrupt or exception handler the image
    defines (a strong *_Handler / *_IRQHandler symbol in the ELF; the weak
    aliases of Default_Handler count as Default_Handler);
  * the worst total: the background chain, plus for every handler its chain
    and one exception frame with the FP context (26 words: r0-r3, r12, lr, pc,
    xPSR, s0-s15, FPSCR, reserved; ARMv7-M ARM B1.5.7) and the 4-byte
    alignment word, as if every handler preempted the one before (each at its
    own priority: an upper bound, whatever the priorities are).

Calls through a pointer (GCC's __indirect_call) are resolved to every function
of the image that is never called directly (callbacks, handlers registered at
run time such as drive_isr) and is not already running in the chain (a
callback does not re-enter itself; a cycle that passes through such a call is
an artefact of this over-approximation and is not followed): the worst of
those, an upper bound. Functions
without call-graph information (newlib, libgcc) get a fixed allowance and are
listed. Recursion in an interrupt's chain, or a dynamically sized frame, is
an error; recursion in the background is reported and followed once.

usage: stack_check.py BUILD_DIR LINKER_SCRIPT [--reserve BYTES] [--elf ELF]
exit:  0 the worst total fits the reserve (DTC_MIN_STACK of the linker script),
       1 it does not, or the analysis failed; 77 the target build is missing.
"""
import argparse
import json
import os
import re
import subprocess
import sys

FP_FRAME_BYTES = 26 * 4 + 4  # extended frame + alignment padding
EXTERNAL_ALLOWANCE = 64      # bytes allowed to a library function without .ci (newlib memcpy/memset use < 32)
SKIP_DIRS = ("hal/pil",)     # the PIL programs are not part of the image

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]+)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")


def current_ci_files(build):
    """The .ci files of the objects the build compiles now (compile_commands.json),
    or None when it cannot tell: a build directory keeps the .ci files of objects
    it no longer builds (e.g. per-file ones after a library became a unity unit),
    and their stale frames must not count."""
    try:
        with open(os.path.join(build, "compile_commands.json"), encoding="utf-8") as fh:
            entries = json.load(fh)
    except (OSError, ValueError):
        return None
    out = set()
    for e in entries:
        m = re.search(r"(?:^|\s)-o\s+(\S+)", e.get("command", ""))
        if not m:
            return None
        obj = os.path.normpath(os.path.join(e.get("directory", build), m.group(1)))
        out.add(os.path.splitext(obj)[0] + ".ci")
    return out


def load_graph(build):
    frames, kinds, edges = {}, {}, {}
    current = current_ci_files(build)
    for dirpath, _dirs, files in os.walk(build):
        rel = os.path.relpath(dirpath, build)
        if any(s in rel for s in SKIP_DIRS):
            continue
        for f in files:
            if not f.endswith(".ci"):
                continue
            if current is not None and os.path.normpath(os.path.abspath(os.path.join(dirpath, f))) not in current:
                continue  # left over from an object the build no longer has
            with open(os.path.join(dirpath, f), encoding="utf-8") as fh:
                for line in fh:
                    m = NODE.search(line)
                    if m:
                        fr = FRAME.search(m.group(2))
                        if fr:
                            frames[m.group(1)] = int(fr.group(1))
                            kinds[m.group(1)] = fr.group(2)
                        continue
                    m = EDGE.search(line)
                    if m:
                        edges.setdefault(m.group(1), set()).add(m.group(2))
    return frames, kinds, edges


def short(name):
    return name.rsplit(":", 1)[-1]


def elf_functions(elf):
    out = subprocess.run(["arm-none-eabi-nm", "--defined-only", elf], capture_output=True, text=True, check=True)
    funcs = {}
    for line in out.stdout.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            funcs[parts[2]] = (int(parts[0], 16), parts[1])
    return funcs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build")
    ap.add_argument("linker_script")
    ap.add_argument("--elf", help="default BUILD/dtc-fw.elf")
    ap.add_argument("--reserve", type=int, help="override the linker script's DTC_MIN_STACK, bytes")
    ap.add_argument("--indirect", action="append", default=[], metavar="CALLER=TARGET[,TARGET]",
                    help="the calls through a pointer in CALLER go to these functions only "
                         "(e.g. ADC1_2_IRQHandler=drive_isr: the one handler main.c registers with hal_tick_start)")
    a = ap.parse_args()

    elf = a.elf or os.path.join(a.build, "dtc-fw.elf")
    if not os.path.isfile(elf):
        print(f"stack_check: {elf} not found (build the stm32g4 preset first)")
        return 77
    with open(a.linker_script, encoding="utf-8") as fh:
        m = re.search(r"^DTC_MIN_STACK\s*=\s*(\d+)\s*([Kk]?)\s*;", fh.read(), re.M)
    if not m:
        print(f"stack_check: no DTC_MIN_STACK in {a.linker_script}")
        return 1
    reserve = int(m.group(1)) * (1024 if m.group(2) else 1)
    if a.reserve is not None:
        reserve = a.reserve

    frames, kinds, edges = load_graph(a.build)
    if not frames:
        print(f"stack_check: no call-graph files (*.ci) under {a.build}: configure the stm32g4 preset again")
        return 77
    funcs = elf_functions(elf)
    # Titles: global functions by name, static ones as FILE:name. Keep the
    # ones linked into the image (gc-sections drops the rest).
    in_image = {t for t in frames if short(t) in funcs}
    called = set()
    for src, dsts in edges.items():
        if src in in_image:
            called.update(d for d in dsts if d != "__indirect_call")
    default_addr = funcs.get("Default_Handler", (None,))[0]
    handlers = sorted(n for n, (addr, _t) in funcs.items()
                      if re.search(r"_(IRQ)?Handler$", n) and n != "Reset_Handler"
                      and (addr != default_addr or n == "Default_Handler"))
    indirect_targets = sorted(t for t in in_image if t not in called and short(t) not in handlers
                              and short(t) not in ("Reset_Handler", "main"))

    per_caller = {}
    for spec in a.indirect:
        caller, _, targets = spec.partition("=")
        titles = [t for t in frames if short(t) in targets.split(",")]
        if not targets or len(titles) != len(targets.split(",")):
            print(f"stack_check: --indirect {spec}: a target is not in the image")
            return 1
        per_caller[caller] = titles
    indirect_set = set(indirect_targets)
    cycles = set()
    allow_cycles = [False]
    externals = set()
    memo = {}

    def resolve(name):
        if name in frames:
            return name
        return name  # an external (no .ci) function

    def depth(name, stack, vias=(), entered_via=False):
        """(bytes, chain) of the deepest path from name, or None for a path
        that only the pointer over-approximation creates (a cycle through a
        call through a pointer)."""
        name = resolve(name)
        if name in stack:
            i = stack.index(name)
            if any(vias[i + 1:]) or entered_via:
                return None
            cycle = " -> ".join(short(s) for s in stack[i:] + [name])
            if not allow_cycles[0]:
                raise RuntimeError("recursion: " + cycle)
            cycles.add(cycle)
            return None
        key = (name, frozenset(stack))
        if key in memo:
            return memo[key]
        if name not in frames:
            externals.add(name)
            return EXTERNAL_ALLOWANCE, [f"{short(name)} (no call graph: {EXTERNAL_ALLOWANCE} allowed)"]
        if kinds[name] != "static":
            raise RuntimeError(f"{short(name)}: frame is {kinds[name]}, not static")
        best, chain = 0, []
        for callee in sorted(edges.get(name, ())):
            # A callback does not re-enter a callback that is still running.
            if callee != "__indirect_call":
                targets = [callee]
            elif short(name) in per_caller:
                targets = per_caller[short(name)]
            else:
                targets = [t for t in indirect_targets if t not in stack]
            for t in targets:
                r = depth(t, stack + [name], vias + (entered_via,), callee == "__indirect_call")
                if r is None:
                    continue
                d, c = r
                if d > best:
                    best, chain = d, (["(through a pointer)"] if callee == "__indirect_call" else []) + c
        memo[key] = (frames[name] + best, [f"{short(name)} {frames[name]}"] + chain)
        return memo[key]

    def root_title(sym):
        for t in frames:
            if short(t) == sym:
                return t
        return sym

    try:
        allow_cycles[0] = True  # the background: a cycle is reported, followed once
        bg, bg_chain = depth(root_title("Reset_Handler"), [])
        allow_cycles[0] = False  # interrupts: recursion is an error
        memo.clear()
        rows = []
        for h in handlers:
            d, c = depth(root_title(h), [])
            rows.append((h, d, c))
    except RuntimeError as e:
        print(f"stack_check: FAIL: {e}")
        return 1

    total = bg + sum(FP_FRAME_BYTES + d for _h, d, _c in rows)
    print(f"stack_check: {elf}")
    print(f"background  {bg:5d} bytes: {' -> '.join(bg_chain)}")
    for h, d, c in sorted(rows, key=lambda r: -r[1]):
        print(f"{h:<28s} {d:5d} bytes + {FP_FRAME_BYTES} exception frame (FP context): {' -> '.join(c)}")
    for c in sorted(cycles):
        print(f"WARNING: background recursion {c}: followed once (one pass through the cycle); "
              "its depth is not bounded by the call graph alone")
    for c, t in per_caller.items():
        print(f"calls through a pointer in {c}: {', '.join(short(x) for x in t)} (as given)")
    print(f"other calls through a pointer resolved to any of: {', '.join(short(t) for t in indirect_targets)}")
    if externals:
        print(f"library functions without call graph ({EXTERNAL_ALLOWANCE} bytes each): "
              f"{', '.join(sorted(short(e) for e in externals))}")
    print(f"worst total, every handler nesting on the background: {total} bytes; "
          f"reserve (DTC_MIN_STACK): {reserve} bytes")
    if total > reserve:
        print("stack_check: FAIL: the worst nesting exceeds the stack reserve")
        return 1
    print(f"stack_check: ok ({reserve - total} bytes to spare)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
