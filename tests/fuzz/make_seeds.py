#!/usr/bin/env python3
"""Write the seed programs of fuzz_canopen_drive (tests/fuzz/corpus/canopen_drive).

usage: make_seeds.py PARAM_TABLE_H OUT_DIR

PARAM_TABLE_H is the generated dtc/param_table.h (entry positions CO_P_*);
the step encoding is the one in fuzz_canopen_drive.cpp's file comment. The
seeds are starting points: a changed table moves the positions, and a stale
seed is still a valid program.
"""
import re
import struct
import sys

FRAME, FRAME_TO, TICKS, PASS, SDO_WRITE, SDO_READ, ENABLE, TIME, BUS_OFF, POWER_CUT, POWER_CYCLE, SAVE = range(12)
TO_NMT, TO_SYNC, TO_SDO, TO_RPDO, TO_HEARTBEAT = range(5)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    pos = {}
    for m in re.finditer(r"CO_P_(\w+) = (\d+),", open(argv[1]).read()):
        pos[m.group(1).lower()] = int(m.group(2))

    def write(name, value):
        """sdo_write of entry `name` with the raw bus word `value` (how = 7: as given)."""
        v = struct.unpack("<I", struct.pack("<f", value))[0] if isinstance(value, float) else value & 0xFFFFFFFF
        return [SDO_WRITE, *struct.pack(">H", pos[name]), 7] + list(struct.pack("<I", v))

    def edge(name, how):
        return [SDO_WRITE, *struct.pack(">H", pos[name]), how, 0, 0, 0, 0]

    ticks = [TICKS, 15, 0, 0, 0, 0]
    rpdo = lambda cw, rpm: [FRAME_TO, TO_RPDO, 6] + list(struct.pack("<Hi", cw, rpm))
    nmt = lambda cmd, node: [FRAME_TO, TO_NMT, 2, cmd, node]
    seeds = {
        "target_2500_each_object": [*nmt(1, 1), PASS, ENABLE, 0, *write("target_velocity", 2500), *ticks,
                                    *write("vl_target_velocity", 2500), *ticks, *rpdo(0x0F, 2500), PASS, *ticks,
                                    *write("speed_ref_rpm", 2500.0), PASS],
        "vl_min_above_max": [*write("target_velocity", 50), *write("vl_velocity_min", 3000),
                             *write("vl_velocity_max", 3000), *write("vl_velocity_min", 3000),
                             *write("vl_velocity_max", 100), *write("vl_velocity_min", 0),
                             *write("vl_velocity_max", 100), PASS],
        "vl_limits_edges": [*write("vl_target_velocity", -2000), *edge("vl_velocity_min", 1),
                            *edge("vl_velocity_max", 0), *edge("vl_velocity_max", 3), *edge("vl_velocity_min", 3),
                            *edge("target_velocity", 1), *edge("target_velocity", 0), PASS],
        "overspeed_then_vl": [*write("target_velocity", 2500), *write("overspeed_rad_s", 100.0),
                              *write("vl_velocity_max", 500), *write("overspeed_rad_s", 500.0),
                              *write("vl_velocity_max", 3000), PASS],
        "save_cut_and_cycle": [*write("vl_velocity_max", 1000), *write("te_max_nm", 50.0), SAVE,
                               *write("vl_velocity_max", 2000), POWER_CUT, 3, PASS, *write("vl_velocity_max", 900),
                               POWER_CUT, 40, POWER_CYCLE, PASS, SAVE, POWER_CYCLE, PASS],
        "reset_node_reloads": [*write("vl_velocity_max", 1000), SAVE, *write("vl_velocity_max", 3000),
                               *write("vl_target_velocity", 2650), *nmt(0x81, 1), PASS, PASS, PASS,
                               *write("restore_all", 0x64616F6C), PASS],
        "bus_off_while_running": [*nmt(1, 1), PASS, ENABLE, 0, *write("target_velocity", 500), *ticks, *ticks,
                                  BUS_OFF, 1, PASS, TIME, 50, PASS, BUS_OFF, 0, PASS, *ticks, PASS],
        "heartbeat_lost": [*write("hb_consumer", (0x7F << 16) | 300), *nmt(1, 1), PASS, ENABLE, 0,
                           *ticks, FRAME_TO, TO_HEARTBEAT, 1, 5, PASS, TIME, 100, PASS,
                           *ticks, PASS],
        "halt_and_quick_stop": [*nmt(1, 1), PASS, ENABLE, 1, *write("target_velocity", 800), *ticks, ENABLE, 0,
                                *ticks, *write("controlword", 0x02), *ticks, PASS],
        "nmt_commands": [*nmt(1, 0), PASS, *nmt(0x80, 1), PASS, *nmt(2, 1), PASS, *nmt(0x82, 0), PASS, PASS,
                         *nmt(0x81, 0), PASS, PASS, PASS],
        "raw_frames": [FRAME, 0x06, 0x01, 8, 0x2B, 0x00, 0x25, 0x03, 0xE8, 0x03, 0, 0, PASS,
                       FRAME, 0x02, 0x01, 3, 1, 2, 3, PASS, FRAME, 0x00, 0x80, 0, PASS,
                       SDO_READ, *struct.pack(">H", pos["speed_ref_rpm"]), SDO_READ, *struct.pack(">H", pos["vl_velocity_max"]), PASS],
        "samples_that_trip": [*nmt(1, 1), PASS, ENABLE, 0, TICKS, 15, 0x7F, 0x80, 0x7F, 0x80, PASS,
                              *write("controlword", 0x80), PASS, ENABLE, 0, TICKS, 15, 1, 2, 3, 4, PASS],
    }
    for name, prog in seeds.items():
        with open(f"{argv[2]}/{name}.bin", "wb") as fh:
            fh.write(bytes(b & 0xFF for b in prog))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
