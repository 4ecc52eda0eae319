#!/usr/bin/env python3
"""Renders a labelled cloud from a bag as a PNG: top-down view and perspective view, every point
in its label's palette colour. Needs no display (matplotlib's Agg backend).

    render_labelled.py OUTPUT_BAG OUT.png [--topic /ring_curvature/labelled_points] [--index -1]
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import rosbag  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import label_palette  # noqa: E402

# sensor_msgs/PointField datatypes -> numpy
DTYPES = {1: "i1", 2: "u1", 3: "<i2", 4: "<u2", 5: "<i4", 6: "<u4", 7: "<f4", 8: "<f8"}


def fields_of(cloud, names):
    """Columns of the named fields, read by name and offset from the raw records."""
    rows = np.frombuffer(cloud.data, dtype=np.uint8).reshape(cloud.height, cloud.row_step)
    records = np.ascontiguousarray(rows[:, : cloud.width * cloud.point_step]).reshape(-1, cloud.point_step)
    by_name = {f.name: f for f in cloud.fields}
    out = []
    for n in names:
        f = by_name[n]
        dt = np.dtype(DTYPES[f.datatype])
        raw = np.ascontiguousarray(records[:, f.offset: f.offset + dt.itemsize])
        out.append(raw.view(dt).reshape(-1))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bag")
    ap.add_argument("png")
    ap.add_argument("--topic", default="/ring_curvature/labelled_points")
    ap.add_argument("--index", type=int, default=-1, help="which message of the topic (default: last)")
    args = ap.parse_args()

    with rosbag.Bag(args.bag) as bag:
        msgs = [m for _, m, _ in bag.read_messages(topics=[args.topic])]
    if not msgs:
        print("no %s in %s" % (args.topic, args.bag), file=sys.stderr)
        return 1
    cloud = msgs[args.index]
    x, y, z, label = fields_of(cloud, ["x", "y", "z", "label"])
    ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(z)
    x, y, z, label = (a[ok].astype(np.float64) for a in (x, y, z, label))
    label = label.astype(int)
    palette = np.array(label_palette.load(), dtype=float) / 255.0

    rng = np.hypot(x, y)
    reach = max(np.percentile(rng, 98), 1.0) if rng.size else 10.0
    fig = plt.figure(figsize=(14, 7), facecolor="#1e1e1e")
    top = fig.add_subplot(1, 2, 1)
    persp = fig.add_subplot(1, 2, 2, projection="3d")
    # None first, then the labels in order of rarity, so edges and corners are drawn on top.
    for value, size in ((0, 0.6), (4, 1.0), (1, 1.0), (2, 2.5), (3, 2.5)):
        sel = label == value
        name = label_palette.LABELS[value]
        top.scatter(x[sel], y[sel], s=size, c=[palette[value]], linewidths=0,
                    label="%s (%d)" % (name, sel.sum()))
        persp.scatter(x[sel], y[sel], z[sel], s=size, c=[palette[value]], linewidths=0, depthshade=False)
    for ax in (top, persp):
        ax.set_facecolor("#1e1e1e")
        ax.tick_params(colors="#bbbbbb")
    top.set_aspect("equal")
    top.set_xlim(-reach, reach)
    top.set_ylim(-reach, reach)
    top.set_xlabel("x [m]", color="#bbbbbb")
    top.set_ylabel("y [m]", color="#bbbbbb")
    top.set_title("top-down, frame '%s', stamp %.3f" % (cloud.header.frame_id, cloud.header.stamp.to_sec()),
                  color="#dddddd")
    leg = top.legend(loc="upper right", markerscale=6, facecolor="#2a2a2a", labelcolor="#dddddd", fontsize=9)
    leg.get_frame().set_edgecolor("#555555")
    persp.set_xlim(-reach, reach)
    persp.set_ylim(-reach, reach)
    persp.set_zlim(-reach / 2, reach / 2)
    persp.view_init(elev=30, azim=-120)
    persp.xaxis.set_pane_color((0.12, 0.12, 0.12, 1))
    persp.yaxis.set_pane_color((0.12, 0.12, 0.12, 1))
    persp.zaxis.set_pane_color((0.12, 0.12, 0.12, 1))
    persp.set_title("perspective", color="#dddddd")
    fig.tight_layout(rect=(0, 0.02, 1, 0.97))
    fig.savefig(args.png, dpi=100, facecolor=fig.get_facecolor())
    print(args.png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
