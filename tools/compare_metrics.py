#!/usr/bin/env python3
"""Compare two folders of dtc-sim metrics JSON files field by field, exactly.

Used to prove a refactor changes no behaviour: every field must be equal
(bit for bit, as JSON numbers), except the host's wall-clock statistics,
which depend on the machine's load and not on the firmware:
wall_seconds, isr_max_us, isr_overruns.

  tools/compare_metrics.py BEFORE_DIR AFTER_DIR   # exit 0 when all identical
"""
import json
import sys
from pathlib import Path

WALL_CLOCK = {"wall_seconds", "isr_max_us", "isr_overruns"}


def main(argv: list[str]) -> int:
    if len(argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    before, after = Path(argv[1]), Path(argv[2])
    files = sorted(before.glob("*.json"))
    if not files:
        print(f"{before}: no *.json files", file=sys.stderr)
        return 2
    differ = 0
    for f in files:
        other = after / f.name
        if not other.is_file():
            print(f"{f.name}: missing in {after}")
            differ += 1
            continue
        a, b = json.loads(f.read_text()), json.loads(other.read_text())
        keys = (set(a) | set(b)) - WALL_CLOCK
        diff = sorted(k for k in keys if a.get(k) != b.get(k))
        print(f"{f.name}: " + (f"identical ({len(keys)} fields)" if not diff else f"DIFFERENT in {diff}"))
        differ += bool(diff)
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
