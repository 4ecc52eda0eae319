#!/usr/bin/env python3
"""Prints one summary line per frame the ring_curvature nodelet outputs: points, label counts,
primitives and processing time, then the nodelet's /diagnostics view.

Processing time is the nodelet's own measurement from ~frame_stats: callback entry to the last
publish ("processing"), of which the core's stages ("core"). Latency is measured here, from this
process seeing the input cloud to it seeing the labelled cloud with the same stamp; it adds two
message transports to the processing.

Exits 0 once --frames frames were summarised, 1 on timeout.
"""
import argparse
import sys
import threading
import time

import numpy as np
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import PointCloud2

from ring_curvature.msg import FrameStats, PrimitiveArray

LABELS = ("none", "plane", "edge", "corner", "rough")


def label_counts(cloud):
    """Counts of each label value, read from the uint8 `label` field by its offset."""
    field = next((f for f in cloud.fields if f.name == "label"), None)
    if field is None or field.datatype != 2:  # 2 = UINT8
        raise ValueError("labelled cloud has no uint8 'label' field")
    rows = np.frombuffer(cloud.data, dtype=np.uint8).reshape(cloud.height, cloud.row_step)
    records = rows[:, : cloud.width * cloud.point_step].reshape(-1, cloud.point_step)
    return np.bincount(records[:, field.offset], minlength=len(LABELS)), records.shape[0]


def fmt_ms(value):
    try:
        return "%.2f" % float(value)
    except (TypeError, ValueError):
        return "?"


class Summary:
    def __init__(self, ns, want):
        self.want = want
        self.lock = threading.Lock()
        self.input_seen = {}   # stamp -> monotonic time the input was seen
        self.labelled = {}     # stamp -> (counts, points, latency ms)
        self.primitives = {}   # stamp -> count
        self.stats = {}        # stamp -> FrameStats
        self.printed = 0
        self.done = threading.Event()
        self.diag = None
        self.node_name = ns.strip("/")

    def on_input(self, msg):
        with self.lock:
            self.input_seen[msg.header.stamp] = time.monotonic()

    def on_labelled(self, msg):
        now = time.monotonic()
        counts, points = label_counts(msg)
        with self.lock:
            seen = self.input_seen.get(msg.header.stamp)
            latency = (now - seen) * 1e3 if seen is not None else float("nan")
            self.labelled[msg.header.stamp] = (counts, points, latency)
            self.flush()

    def on_primitives(self, msg):
        with self.lock:
            self.primitives[msg.header.stamp] = len(msg.primitives)
            self.flush()

    def on_stats(self, msg):
        with self.lock:
            self.stats[msg.header.stamp] = msg
            self.flush()

    def on_diag(self, msg):
        for status in msg.status:
            if self.node_name in status.name and any(kv.key == "time total [ms]" for kv in status.values):
                with self.lock:
                    self.diag = status

    def diag_value(self, key):
        if self.diag is None:
            return None
        return next((kv.value for kv in self.diag.values if kv.key == key), None)

    def flush(self):
        for stamp in sorted(set(self.labelled) & set(self.primitives) & set(self.stats)):
            counts, points, latency = self.labelled.pop(stamp)
            prims = self.primitives.pop(stamp)
            st = self.stats.pop(stamp)
            core = (st.grid_ms + st.features_ms + st.thresholds_ms + st.classification_ms
                    + st.primitives_ms + st.core_output_ms)
            self.printed += 1
            label_text = "  ".join("%s %d" % (n, c) for n, c in zip(LABELS, counts))
            print("frame %d  stamp %.3f  points %d  %s  primitives %d  processing %.2f ms (core %.2f)"
                  "  latency %.1f ms"
                  % (self.printed, stamp.to_sec(), points, label_text, prims, st.callback_ms, core, latency),
                  flush=True)
            if self.printed >= self.want:
                self.done.set()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ns", default="/ring_curvature", help="the nodelet's private namespace")
    ap.add_argument("--input", default="/velodyne_points", help="the nodelet's input topic")
    ap.add_argument("--frames", type=int, required=True, help="frames to wait for")
    ap.add_argument("--timeout", type=float, default=60.0, help="give up after this many seconds")
    args = ap.parse_args(rospy.myargv()[1:])

    rospy.init_node("frame_summary", anonymous=True, disable_signals=True)
    s = Summary(args.ns, args.frames)
    ns = args.ns.rstrip("/")
    subs = [rospy.Subscriber(args.input, PointCloud2, s.on_input, queue_size=10, buff_size=1 << 24),
            rospy.Subscriber(ns + "/labelled_points", PointCloud2, s.on_labelled, queue_size=10,
                             buff_size=1 << 24),
            rospy.Subscriber(ns + "/primitives", PrimitiveArray, s.on_primitives, queue_size=10,
                             buff_size=1 << 24),
            rospy.Subscriber(ns + "/frame_stats", FrameStats, s.on_stats, queue_size=10),
            rospy.Subscriber("/diagnostics", DiagnosticArray, s.on_diag, queue_size=10)]
    ok = s.done.wait(args.timeout)
    # The diagnostic updater publishes every 1-2 s: wait for a status that covers every frame.
    end = time.monotonic() + 4.0
    while ok and time.monotonic() < end:
        with s.lock:
            processed = s.diag_value("frames processed")
        if processed is not None and int(processed) >= s.printed:
            break
        time.sleep(0.1)
    with s.lock:
        diag = s.diag
    if diag is not None:
        values = {kv.key: kv.value for kv in diag.values}
        stages = ["grid", "features", "thresholds", "classification", "primitives", "messages",
                  "total"]
        print("nodelet diagnostics, last frame processed: "
              + "  ".join("%s %s ms" % (k, fmt_ms(values.get("time %s [ms]" % k))) for k in stages)
              + "  (frames processed %s, rejected %s)"
              % (values.get("frames processed", "?"), values.get("frames rejected", "?")), flush=True)
    else:
        print("nodelet diagnostics: none received", flush=True)
    for sub in subs:
        sub.unregister()
    if not ok:
        print("timed out after %.0f s: %d of %d frames summarised" % (args.timeout, s.printed, args.frames),
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
