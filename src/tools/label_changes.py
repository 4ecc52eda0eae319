#!/usr/bin/env python3
"""Counts the points whose label differs between two builds' outputs.

compare_outputs.sh tells whether two builds' output bags are identical; when a change is meant to
move the outputs (e.g. features computed in float32), this says by how much: run
`src/tools/compare_outputs.sh BEFORE_DIR AFTER_DIR WORK_DIR` (WORK_DIR keeps the bags), then
`src/tools/label_changes.py WORK_DIR`. One line per run (bag and parameter set) with its frames,
points and changed labels (field `label` of ~labelled_points), and the totals.
"""
import glob
import os
import sys

import rosbag


def labels(path):
    """Every frame's label bytes, in order."""
    frames = []
    with rosbag.Bag(path) as bag:
        for topic, msg, _ in bag.read_messages():
            if not topic.endswith('labelled_points'):
                continue
            field = next(f for f in msg.fields if f.name == 'label')
            frames.append(bytes(msg.data[field.offset::msg.point_step]))
    return frames


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    total_points = total_changes = 0
    for before in sorted(glob.glob(os.path.join(sys.argv[1], '*.before.bag'))):
        name = os.path.basename(before)[:-len('.before.bag')]
        a, b = labels(before), labels(before.replace('.before.bag', '.after.bag'))
        if len(a) != len(b) or any(len(x) != len(y) for x, y in zip(a, b)):
            sys.exit(f'{name}: the two outputs have different frames or points')
        changes = sum(sum(p != q for p, q in zip(x, y)) for x, y in zip(a, b))
        points = sum(len(x) for x in a)
        total_points += points
        total_changes += changes
        print(f'{name:60s} frames={len(a)} points={points} label_changes={changes}')
    print(f'total points={total_points} label_changes={total_changes}')


if __name__ == '__main__':
    main()
