#!/usr/bin/env python3
"""Checks an rviz screenshot for labelled points drawn in the label palette.

    check_screenshot.py SHOT.png --require plane:400 --require edge:100 [--tolerance 30]
                        [--view-background 30,30,30]
    check_screenshot.py --config config/ring_curvature.rviz

With a PNG: counts the pixels within --tolerance (RGB distance) of each palette colour and fails
unless every --require LABEL:N is met. A screenshot of rviz before any cloud arrived has (nearly)
none of these pixels, so the check fails there (scripts/test.d/30-rviz-screenshot asserts that too).
With --config: fails unless the rviz config draws the labelled cloud, planes and edges displays
in the palette's colours.
"""
import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "scripts"))
import label_palette  # noqa: E402


def count_pixels(png, tolerance, background=None):
    img = mpimg.imread(png)
    if img.dtype != np.uint8:  # PNGs load as float in [0, 1]
        img = np.rint(img * 255.0)
    img = img[..., :3].astype(np.float64)
    if background is not None:
        # Only the 3-D view: the bounding box of the pixels in rviz's background colour. The
        # panels around it hold greys and blue text that are not drawn points.
        # (Rows and columns mostly of that colour: stray dark pixels in text do not count.)
        is_bg = np.all(img == np.array(background, dtype=np.float64), axis=2)
        rows = np.nonzero(is_bg.mean(axis=1) > 0.2)[0]
        cols = np.nonzero(is_bg.mean(axis=0) > 0.2)[0]
        if rows.size == 0 or cols.size == 0:
            raise SystemExit("no area of the background colour %s: is this an rviz screenshot?" % (background,))
        img = img[rows.min(): rows.max() + 1, cols.min(): cols.max() + 1]
    rgb = img.reshape(-1, 3)
    counts = {}
    for name, colour in zip(label_palette.LABELS, label_palette.load()):
        d = np.linalg.norm(rgb - np.array(colour, dtype=np.float64), axis=1)
        counts[name] = int((d <= tolerance).sum())
    return counts, rgb.shape[0]


def check_png(args):
    bg = tuple(int(v) for v in args.view_background.split(",")) if args.view_background else None
    counts, total = count_pixels(args.png, args.tolerance, bg)
    print("%s: %d pixels; near palette (tolerance %g): %s" % (
        args.png, total, args.tolerance, "  ".join("%s %d" % kv for kv in counts.items())))
    failures = []
    for req in args.require:
        name, _, n = req.partition(":")
        if name not in counts:
            raise SystemExit("unknown label %r in --require (labels: %s)" % (name, ", ".join(counts)))
        if counts[name] < int(n):
            failures.append("%s: %d pixels < %s required" % (name, counts[name], n))
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


def display_blocks(text):
    """(name, block text) of each display in an rviz config."""
    parts = re.split(r"\n    - ", text)
    for part in parts[1:]:
        m = re.search(r"^\s*Name: (.*)$", part, re.M)
        yield (m.group(1).strip() if m else "", part)


def colour_of(block, key):
    m = re.search(r"^\s*%s: (\d+); (\d+); (\d+)\s*$" % re.escape(key), block, re.M)
    return tuple(int(v) for v in m.groups()) if m else None


def check_config(path):
    palette = dict(zip(label_palette.LABELS, label_palette.load()))
    blocks = {}
    for name, block in display_blocks(open(path).read()):
        topic = re.search(r"^\s*Topic: (\S+)", block, re.M)
        if topic:
            blocks[topic.group(1).rsplit("/", 1)[-1]] = block
    expected = [("labelled_points", "Min Color", "none"), ("labelled_points", "Max Color", "rough"),
                ("planes", "Color", "plane"), ("edges", "Color", "edge")]
    failures = []
    for topic, key, label in expected:
        block = blocks.get(topic)
        got = colour_of(block, key) if block else None
        if got != palette[label]:
            failures.append("%s display %s is %s, palette %s is %s" % (topic, key, got, label, palette[label]))
    lab = blocks.get("labelled_points", "")
    for key, want in (("Channel Name", "label"), ("Min Intensity", "0"), ("Max Intensity", "4"),
                      ("Autocompute Intensity Bounds", "false"), ("Color Transformer", "Intensity")):
        m = re.search(r"^\s*%s: (\S+)\s*$" % re.escape(key), lab, re.M)
        if not m or m.group(1) != want:
            failures.append("labelled_points display: %s should be %s" % (key, want))
    for f in failures:
        print("FAIL " + f)
    if not failures:
        print("%s: display colours match kLabelPalette" % path)
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png", nargs="?")
    ap.add_argument("--require", action="append", default=[], metavar="LABEL:N")
    ap.add_argument("--tolerance", type=float, default=30.0)
    ap.add_argument("--view-background", metavar="R,G,B",
                    help="count only inside the area of this colour (rviz's 3-D view background)")
    ap.add_argument("--config")
    args = ap.parse_args()
    if args.config:
        return check_config(args.config)
    if not args.png:
        ap.error("give a PNG or --config")
    return check_png(args)


if __name__ == "__main__":
    sys.exit(main())
