#!/usr/bin/env python3
"""Refuse a Cortex-M4F image that contains double-precision floating point.

The FPU of the Cortex-M4F is single precision only: every double operation
becomes a software routine (``__aeabi_dmul``, ``__adddf3``, ...) tens of times
slower than the float instruction, which the control interrupt cannot afford.
This check lists such routines and double libm functions (``sin``, ``exp``,
...) defined in the linked image, and for each one the functions that call
it, found in the image's own disassembly (so inlining is already resolved).

usage: check_no_double.py [--nm NM] [--objdump OBJDUMP] image.elf
exit:  0 clean, 1 double-precision code found, 2 tool or usage error
"""
import argparse
import re
import subprocess
import sys

# ARM run-time ABI double helpers and their GCC libgcc names.
HELPER = re.compile(
    r"^(__aeabi_(dadd|dsub|drsub|dmul|ddiv|dneg|dcmp(eq|lt|le|ge|gt|un)|cdcmpeq|cdcmple|cdrcmple"
    r"|d2f|f2d|d2iz|d2uiz|d2lz|d2ulz|i2d|ui2d|l2d|ul2d)"
    r"|__(add|sub|mul|div|neg)df3|__extendsfdf2|__truncdfsf2"
    r"|__fix(uns)?df(si|di)|__float(un)?(si|di)df|__(eq|ne|lt|le|gt|ge|unord|cmp)df2"
    # float -> 64-bit integer: libgcc converts through double (libgcc2.c)
    r"|__aeabi_f2u?lz|__fix(uns)?sfdi)$"
)
# Double-precision C library functions (their float twins end in 'f').
LIBM_DOUBLE = {
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
    "exp", "exp2", "expm1", "log", "log2", "log10", "log1p", "pow", "sqrt", "cbrt",
    "hypot", "fma", "fmod", "remainder", "floor", "ceil", "round", "lround", "trunc",
    "modf", "frexp", "ldexp", "scalbn", "strtod", "atof",
}


def run(cmd):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as exc:
        print(f"check_no_double: cannot run {cmd[0]}: {exc}", file=sys.stderr)
        sys.exit(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nm", default="arm-none-eabi-nm")
    ap.add_argument("--objdump", default="arm-none-eabi-objdump")
    ap.add_argument("elf")
    args = ap.parse_args()

    defined = set()
    for line in run([args.nm, "--defined-only", args.elf]).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TtWw":
            defined.add(parts[2])
    bad = sorted(s for s in defined if HELPER.match(s) or s in LIBM_DOUBLE)
    if not bad:
        print(f"check_no_double: {args.elf}: no double-precision code")
        return 0

    # Who calls them: scan the image's disassembly for branches to each symbol.
    callers = {s: set() for s in bad}
    func = None
    head = re.compile(r"^[0-9a-f]+ <([^>]+)>:$")
    target = re.compile(r"\sb(l|lx|\.w|\.n)?(\s|\.)[^<]*<([^>+]+)(\+0x[0-9a-f]+)?>")
    for line in run([args.objdump, "-d", args.elf]).splitlines():
        m = head.match(line)
        if m:
            func = m.group(1)
            continue
        m = target.search(line)
        if m and m.group(3) in callers and func != m.group(3):
            callers[m.group(3)].add(func)

    # Report the calls from outside the double routines and library internals:
    # those are the lines to fix.
    entry = {}
    for s, funcs in callers.items():
        for f in funcs:
            if f not in callers and not f.startswith("__"):
                entry.setdefault(f, set()).add(s)
    print(f"check_no_double: {args.elf} contains {len(bad)} double-precision routines:"
          f" {', '.join(bad)}", file=sys.stderr)
    if entry:
        print("  reached from:", file=sys.stderr)
        for f in sorted(entry):
            print(f"    {f} calls {', '.join(sorted(entry[f]))}", file=sys.stderr)
    else:
        print("  (no direct call from project code found: referenced by address)", file=sys.stderr)
    print("  Fix the caller: float variables, float literals (1.0f or R(1.0)), the 'f' libm"
          " functions (sinf, expf, ...), no casts from float to 64-bit integers.", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
