#!/usr/bin/env python3
"""Writes the fuzz seed corpus (test/fuzz/corpus/) from real frames in rosbag_fixtures/.

Each seed is a small, valid slice of a real cloud in the fuzz input format of fuzz_input.hpp:
its own field layout (velodyne's packed 22-byte XYZIRT, ouster's 48-byte records, organized or
not) and real point bytes, so the fuzzer starts from inputs that pass every check and reach the
features, classifier and primitives. Slices stay under a few KB so each execution is fast.

    python3 test/fuzz/make_seeds.py            # rewrites test/fuzz/corpus/seed_*.bin
"""
import os
import struct
import sys

import rosbag

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
NAME_IDS = {"x": 0, "y": 1, "z": 2, "ring": 3, "time": 4, "t": 5, "intensity": 6, "timestamp": 7}
FLAG_FIX_ROW_STEP = 4


def encode(msg, rows, cols, param_bits=0x30, max_rings=256):
    """The first `cols` points of each of `rows` rows (unorganized: a run of `cols` points)."""
    fields = [f for f in msg.fields if f.name in NAME_IDS][:8]
    if msg.height > 1:
        data = b"".join(msg.data[r * msg.row_step: r * msg.row_step + cols * msg.point_step]
                        for r in range(rows))
        width, height = cols, rows
    else:
        data = bytes(msg.data[: rows * cols * msg.point_step])
        width, height = rows * cols, 1
    out = struct.pack("<BBBBIIII", FLAG_FIX_ROW_STEP, param_bits, max_rings - 1, len(fields),
                      width, height, msg.point_step, width * msg.point_step)
    for f in fields:
        out += struct.pack("<BBHI", NAME_IDS[f.name], f.datatype, f.count, f.offset)
    return out + data


def first_cloud(bag_name, skip=0):
    with rosbag.Bag(os.path.join(REPO, "rosbag_fixtures", bag_name)) as bag:
        for i, (_, msg, _) in enumerate(bag.read_messages()):
            if hasattr(msg, "fields") and i >= skip:
                return msg
    raise RuntimeError("no cloud in " + bag_name)


def main():
    corpus = os.path.join(HERE, "corpus")
    os.makedirs(corpus, exist_ok=True)
    vlp = first_cloud("nebula_vlp16_lastreturn_4scans.bag")
    street = first_cloud("rustlidar_velodyne_vlp16_vlp16_1scan.bag")
    ouster = first_cloud("ouster_os2_32_legacy_1frame_organized.bag")
    seeds = {
        # velodyne firing order: 16 consecutive points are one firing of all rings
        "seed_vlp16_indoor.bin": encode(vlp, 16, 12),
        "seed_vlp16_indoor_quartile.bin": encode(vlp, 16, 12, param_bits=0x00),
        "seed_vlp16_street_paper.bin": encode(street, 16, 10, param_bits=0x40),
        "seed_vlp16_street_max8.bin": encode(street, 16, 10, param_bits=0x81, max_rings=8),
        # organized 48-byte ouster records, NaN where there was no return
        "seed_ouster_organized.bin": encode(ouster, 4, 24, param_bits=0x22),
    }
    for name, blob in seeds.items():
        with open(os.path.join(corpus, name), "wb") as f:
            f.write(blob)
        print("%-34s %6d bytes" % (name, len(blob)))


if __name__ == "__main__":
    sys.exit(main())
