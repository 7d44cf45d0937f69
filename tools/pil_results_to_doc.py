#!/usr/bin/env python3
"""Put tools/pil_bench.sh's two tables and its worst ticks into docs/pil.md's "Results today".

usage: tools/pil_bench.sh | tee bench.txt; tools/pil_results_to_doc.py bench.txt [docs/pil.md]

The section's tables are replaced by the bench's, as printed, and the line "Worst ticks (from
the bench): ..." by the bench's worst ticks, so the doc's figures are the last run's, never
typed by hand. Exit status 1 when the bench output lacks a table.
"""
import re
import sys
from pathlib import Path


def tables(text):
    """The bench's markdown tables, in order (each a list of lines)."""
    out, cur = [], []
    for line in text.splitlines():
        if line.startswith("|"):
            cur.append(line)
        elif cur:
            out.append(cur)
            cur = []
    if cur:
        out.append(cur)
    return out


def main(argv):
    bench = Path(argv[1]).read_text()
    doc_path = Path(argv[2] if len(argv) > 2 else Path(__file__).resolve().parents[1] / "docs" / "pil.md")
    doc = doc_path.read_text()
    new = tables(bench)
    if len(new) < 2:
        print("pil_results_to_doc: %s has not both tables of tools/pil_bench.sh" % argv[1], file=sys.stderr)
        return 1
    m = re.search(r"^## Results today\n(.*?)(?=^## )", doc, re.S | re.M)
    if not m:
        print("pil_results_to_doc: %s has no '## Results today' section" % doc_path, file=sys.stderr)
        return 1
    sec = m.group(1)
    old = tables(sec)
    for o, n in zip(old[:2], new[:2]):
        sec = sec.replace("\n".join(o), "\n".join(n), 1)
    worst = re.findall(r"^  (\w+): (\d+) at tick (\d+) \((\w[\w ]*)\) of (\S+)\.rec$", bench, re.M)
    if worst:
        text = "; ".join("%s %s (%s tick %s)" % (c, format(int(n), ","), rec, t) for c, n, t, _, rec in worst)
        sec = re.sub(r"^Worst ticks \(from the bench\):.*$", "Worst ticks (from the bench): %s." % text, sec, flags=re.M)
    cyc = re.findall(r"^  (\w+)\s+max \d+ cyc = ([\d.]+) us \(([\d.]+) \.\. ([\d.]+) us\); mean \d+ cyc = ([\d.]+) us", bench, re.M)
    if cyc:
        text = "; ".join("%s %s µs worst (%s-%s), %s µs mean" % c for c in cyc)
        sec = re.sub(r"^At 170 MHz and 1.5 cycles per instruction \(from the bench\):.*$",
                     "At 170 MHz and 1.5 cycles per instruction (from the bench): %s, of the 200 µs period." % text,
                     sec, flags=re.M)
    doc_path.write_text(doc[:m.start(1)] + sec + doc[m.end(1):])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
