"""A scenario as the flashable image runs it on the emulated board (`dtc-board run`).

The scenario with the image's parameters as flashed: the firmware's defaults (no `[control]`
section; `dtc-board run` would write one into the image's parameter store), and a plant with
the 1 V device drop (`v_on_V = 1`) that the firmware's default `v_drop_V` compensates. Used by tests/board (the twin against dtc-sim, tuning while running)
and by tools/pil_vs_board.py and tools/twin_tick_table.py.
"""


def as_flashed(src, dst):
    """Write SRC without its [control] section and with v_on_V = 1 to DST; return DST."""
    out, skip = [], False
    with open(src) as f:
        for line in f:
            if line.startswith("["):
                skip = line.strip() == "[control]"
            if line.strip().startswith("v_on_V"):
                line = "v_on_V = 1\n"
            if not skip:
                out.append(line)
    with open(dst, "w") as f:
        f.writelines(out)
    return dst
