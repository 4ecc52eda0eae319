"""The label palette, read from kLabelPalette in include/ring_curvature/ros/markers.hpp so that the
C++ markers, the rendered pictures and the screenshot checker cannot disagree."""
import os
import re

LABELS = ("none", "plane", "edge", "corner", "rough")
HEADER = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir,
                      "include", "ring_curvature", "ros", "markers.hpp")


def load(header=HEADER):
    """[(r, g, b)] * 5 in 0..255, indexed by label value."""
    text = open(header).read()
    body = re.search(r"kLabelPalette\s*=\s*\{\{(.*?)\}\};", text, re.S)
    if not body:
        raise ValueError("kLabelPalette not found in %s" % header)
    colours = [tuple(int(v) for v in m) for m in
               re.findall(r"\{\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*\}", body.group(1))]
    if len(colours) != len(LABELS):
        raise ValueError("kLabelPalette in %s has %d colours, expected %d"
                         % (header, len(colours), len(LABELS)))
    return colours
