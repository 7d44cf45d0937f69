#!/usr/bin/env python3
"""Check hal/stm32g4/stm32g474_regs.h against the committed SVD subset.

Every #define of the header must carry a tag (see the header's comment):
@svd* tags are checked (address, field mask, field value, shift, base,
offset), @core and @const are counted. An untagged define, a tag naming a
register or field the subset lacks, or a wrong number fails the check.

    tools/svd/check_regs.py [--header H] [--subset S]
    tools/svd/check_regs.py --pins docs/board.md hal/stm32g4/hal_stm32g4.c

The second form checks that the pin table of docs/board.md and the pin table
of the binding (g_pins) name the same pins, modes and alternate functions, and each gate pin the
same switch ("leg a S3" in the table's signal and in the binding's comment).
Exit status 0 when everything matches, 1 otherwise. Standard library only.
"""
import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import regs_header  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def check_header(header, subset_path):
    with open(subset_path, encoding="utf-8") as f:
        subset = json.load(f)["peripherals"]
    defines = regs_header.parse(header)
    ev = regs_header.Evaluator(defines)
    errors = []
    counts = {"registers": 0, "fields": 0, "bases": 0, "offsets": 0, "core": 0, "const": 0}
    checked_regs, checked_fields = set(), set()

    def where(d):
        return "%s:%d: %s" % (header, d.line, d.name)

    for d in defines:
        if d.name in ("REG32", "REG8", regs_header.GUARD):
            continue
        if d.kind is None:
            errors.append("%s: no @svd/@core/@const tag" % where(d))
            continue
        if d.kind in ("core", "const"):
            counts[d.kind] += 1
            continue
        if d.params is not None:
            errors.append("%s: function-like macro cannot carry an @svd tag" % where(d))
            continue
        target, _, val = d.target.partition("=")
        parts = target.split(".")
        p = subset.get(parts[0])
        if p is None:
            errors.append("%s: peripheral %s not in the subset (run gen_svd_subset.py)" % (where(d), parts[0]))
            continue
        try:
            value = ev.value(d.name)
        except (ValueError, SyntaxError) as e:
            errors.append("%s: %s" % (where(d), e))
            continue
        base = int(p["base"], 16)
        if d.kind == "svd-base":
            counts["bases"] += 1
            if value != base:
                errors.append("%s = 0x%08X, SVD base of %s is 0x%08X" % (where(d), value, parts[0], base))
            continue
        reg = p["registers"].get(parts[1]) if len(parts) > 1 else None
        if reg is None:
            errors.append("%s: register %s not in the subset" % (where(d), target))
            continue
        off = int(reg["offset"], 16)
        if d.kind == "svd-offset":
            counts["offsets"] += 1
            checked_regs.add(target)
            if value != off:
                errors.append("%s = 0x%X, SVD offset of %s is 0x%X" % (where(d), value, target, off))
            continue
        if len(parts) == 2:
            counts["registers"] += 1
            checked_regs.add(target)
            if d.kind != "svd" or val:
                errors.append("%s: a register tag takes no value or shift" % where(d))
            elif value != base + off:
                errors.append("%s = 0x%08X, SVD address of %s is 0x%08X" % (where(d), value, target, base + off))
            continue
        fld = reg["fields"].get(parts[2])
        if fld is None:
            errors.append("%s: field %s not in the subset" % (where(d), target))
            continue
        counts["fields"] += 1
        checked_fields.add(target)
        shift, width = fld["offset"], fld["width"]
        mask = ((1 << width) - 1) << shift
        if d.kind == "svd-shift":
            if value != shift:
                errors.append("%s = %d, SVD bit offset of %s is %d" % (where(d), value, target, shift))
        elif val:
            v = int(val, 0)
            if v >= (1 << width):
                errors.append("%s: value %d does not fit %s (%d bits)" % (where(d), v, target, width))
            elif value != v << shift and value != v:
                errors.append("%s = 0x%X, expected %d << %d = 0x%X" % (where(d), value, v, shift, v << shift))
            elif value == v and shift != 0 and value != v << shift:
                # an unshifted value (e.g. IWDG key, written to a field at bit 0) must sit at bit 0
                errors.append("%s = 0x%X is unshifted but %s starts at bit %d" % (where(d), value, target, shift))
        else:
            if value != mask:
                errors.append("%s = 0x%08X, SVD mask of %s is 0x%08X (bits %d..%d)"
                              % (where(d), value, target, mask, shift, shift + width - 1))
    return errors, counts, checked_regs, checked_fields


PIN_C_RE = re.compile(r"PIN_(AF|ANALOG)\(GPIO([A-G])_BASE,\s*(\d+)u(?:,\s*(\d+)u)?")
# "leg a S3" in a gate pin's comment (binding) or signal (docs/board.md): which switch the pin drives
GATE_RE = re.compile(r"\bleg ([abc]) (S[1-4])\b")


def check_pins(board_md, binding_c):
    errors = []
    with open(binding_c, encoding="utf-8") as f:
        src = f.read()
    c_pins = {}
    for m in PIN_C_RE.finditer(src):
        mode = "AF" if m.group(1) == "AF" else "Analog"
        af = m.group(4) if mode == "AF" else "-"
        line_end = src.find("\n", m.end())
        gate = GATE_RE.search(src[m.end():line_end])
        c_pins["P%s%s" % (m.group(2), m.group(3))] = (mode, af, gate.groups() if gate else None)
    md_pins = {}
    with open(board_md, encoding="utf-8") as f:
        lines = f.read().splitlines()
    try:
        start = lines.index("| Pin | Mode | AF | Signal | Scaling |")
    except ValueError:
        return ["%s: no table with the header '| Pin | Mode | AF | Signal | Scaling |'" % board_md]
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 5:
            errors.append("%s: bad row %r" % (board_md, line))
            continue
        pin, mode, af = cells[0], cells[1], cells[2]
        if pin in md_pins:
            errors.append("%s: %s twice" % (board_md, pin))
        gate = GATE_RE.search(cells[3])
        md_pins[pin] = (mode, af, gate.groups() if gate else None)
    for pin in sorted(set(c_pins) | set(md_pins)):
        if pin not in md_pins:
            errors.append("%s configured by the firmware but not in %s" % (pin, board_md))
        elif pin not in c_pins:
            errors.append("%s in %s but not configured by the firmware" % (pin, board_md))
        elif c_pins[pin] != md_pins[pin]:
            errors.append("%s: firmware %s, %s %s (mode, AF, gate: leg and switch)" % (pin, c_pins[pin], board_md,
                                                                                        md_pins[pin]))
    return errors, len(c_pins)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--header", default=os.path.join(ROOT, "hal/stm32g4/stm32g474_regs.h"))
    ap.add_argument("--subset", default=os.path.join(ROOT, "hal/stm32g4/svd/stm32g474_subset.json"))
    ap.add_argument("--pins", nargs=2, metavar=("BOARD_MD", "BINDING_C"))
    a = ap.parse_args()
    if a.pins:
        res = check_pins(*a.pins)
        if isinstance(res, list):
            errors, n = res, 0
        else:
            errors, n = res
        for e in errors:
            print("check_regs: " + e, file=sys.stderr)
        if errors:
            return 1
        print("check_regs: %d pins, docs table and firmware agree" % n)
        return 0
    errors, counts, regs, fields = check_header(a.header, a.subset)
    for e in errors:
        print("check_regs: " + e, file=sys.stderr)
    print("check_regs: %d register addresses, %d register offsets, %d peripheral bases, %d field "
          "masks/values/shifts (%d distinct registers, %d distinct fields) checked against the SVD "
          "subset; %d Cortex-M core defines, %d constants not in the SVD"
          % (counts["registers"], counts["offsets"], counts["bases"], counts["fields"], len(regs),
             len(fields), counts["core"], counts["const"]))
    if errors:
        print("check_regs: FAILED, %d error(s)" % len(errors), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
