#!/usr/bin/env python3
"""Malformed clouds through the running nodelet (rostest: malformed_nodelet.test).

Publishes, one at a time, each malformed variant of a real VLP-16 frame, waits until the
nodelet's diagnostics report that very rejection (count and a message naming the problem), then
publishes the good frame and waits for its labelled output. Degenerate but legal frames must come
out with the input's shape. Every frame gets its own stamp, so an output can be traced to the frame
it came from: no output may carry a rejected frame's stamp. At the end the diagnostics' received /
processed / rejected counts must equal what was sent.
"""
import math
import os
import struct
import sys
import threading
import time
import unittest

import rosbag
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import PointCloud2, PointField

PKG = "ring_curvature"
HERE = os.path.dirname(os.path.abspath(__file__))
BAG = os.path.join(HERE, "..", "..", "rosbag_fixtures", "nebula_vlp16_lastreturn_4scans.bag")
TIMEOUT = 15.0


def copy(msg):
    out = PointCloud2()
    out.header.frame_id = msg.header.frame_id
    out.height, out.width = msg.height, msg.width
    out.fields = [PointField(f.name, f.offset, f.datatype, f.count) for f in msg.fields]
    out.is_bigendian, out.point_step, out.row_step = msg.is_bigendian, msg.point_step, msg.row_step
    out.data = bytes(msg.data)
    out.is_dense = msg.is_dense
    return out


def field(msg, name):
    return next(f for f in msg.fields if f.name == name)


def set_bytes(msg, offset, blob):
    data = bytearray(msg.data)
    data[offset:offset + len(blob)] = blob
    msg.data = bytes(data)


def points(msg, n, fill):
    """`n` records of the frame's layout, each made by fill(i) -> (x, y, z, ring)."""
    step, f = msg.point_step, {p.name: p for p in msg.fields}
    data = bytearray(n * step)
    for i in range(n):
        x, y, z, ring = fill(i)
        struct.pack_into("<fff", data, i * step + f["x"].offset, x, y, z)
        struct.pack_into("<H", data, i * step + f["ring"].offset, ring)
    out = copy(msg)
    out.width, out.height, out.row_step, out.data = n, 1, n * step, bytes(data)
    return out


def bad_cases(good):
    """(name, corrupt(msg) -> msg, words: the rejection names one of these)."""
    ring = field(good, "ring")

    def drop(name):
        def f(m):
            m.fields = [x for x in m.fields if x.name != name]
            return m
        return f

    def retype(name, datatype):
        def f(m):
            field(m, name).datatype = datatype
            return m
        return f

    def move(name, offset):
        def f(m):
            field(m, name).offset = offset
            return m
        return f

    def attr(**kw):
        def f(m):
            for k, v in kw.items():
                setattr(m, k, v)
            return m
        return f

    def ring300(m):
        set_bytes(m, 5 * m.point_step + ring.offset, struct.pack("<H", 300))
        return m

    def truncate(n):
        def f(m):
            m.data = m.data[:len(m.data) - n]
            return m
        return f

    def oversize(m):
        m.data = m.data + bytes(64)
        return m

    return [
        ("no ring field", drop("ring"), ["'ring'"]),
        # time dropped so that a 4-byte ring fits without overlapping it: only the type is wrong
        ("ring float32", lambda m: retype("ring", PointField.FLOAT32)(drop("time")(m)), ["ring"]),
        ("ring 300 >= max_rings", ring300, ["max_rings"]),
        ("no x", drop("x"), ["'x'"]),
        ("no z", drop("z"), ["'z'"]),
        ("y uint32", retype("y", PointField.UINT32), ["'y'"]),
        ("z past point_step", move("z", 20), ["point_step"]),
        ("y overlaps x", move("y", 2), ["overlap"]),
        ("point_step 0", attr(point_step=0), ["point_step"]),
        ("row_step too small", lambda m: attr(row_step=m.row_step - 1)(m), ["row_step"]),
        ("truncated data", truncate(1), ["bytes", "truncated"]),
        ("half the data", lambda m: truncate(len(m.data) // 2)(m), ["bytes", "truncated"]),
        ("oversized data", oversize, ["bytes"]),
        ("big-endian", attr(is_bigendian=True), ["endian"]),
    ]


def legal_cases(good):
    """(name, msg): degenerate frames that must be processed."""
    nan = float("nan")
    return [
        ("one point", points(good, 1, lambda i: (3.0, 1.0, 0.2, 4))),
        ("all NaN", points(good, 2000, lambda i: (nan, nan, nan, i % 16))),
        ("all identical", points(good, 2000, lambda i: (3.0, 1.0, 0.2, i % 16))),
        ("single ring", points(good, 1800, lambda i: (5.0 * math.cos(i * 0.0035), 5.0 * math.sin(i * 0.0035), 0.0, 0))),
        ("2 million points", points(good, 2000000, lambda i: (5.0, 0.001 * (i % 1000), 0.0001 * (i // 1000), 0))),
    ]


class MalformedThroughNodelet(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.outputs = {}  # stamp (sec) -> labelled cloud
        self.diag = None   # latest {key: value} of the nodelet's status
        self.diag_level = None
        rospy.Subscriber("/ring_curvature/labelled_points", PointCloud2, self.on_output, queue_size=50)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=50)
        self.pub = rospy.Publisher("/velodyne_points", PointCloud2, queue_size=10)
        with rosbag.Bag(BAG) as bag:
            self.good = next(m for _, m, _ in bag.read_messages(topics=["/velodyne_points"]))

    def on_output(self, msg):
        with self.lock:
            self.outputs[msg.header.stamp.secs] = msg

    def on_diag(self, msg):
        for st in msg.status:
            values = {kv.key: kv.value for kv in st.values}
            if "frames rejected" in values:
                with self.lock:
                    self.diag, self.diag_level = values, st.level

    def wait(self, cond, what, timeout=TIMEOUT):
        end = time.time() + timeout
        while time.time() < end and not rospy.is_shutdown():
            with self.lock:
                if cond():
                    return
            time.sleep(0.02)
        self.fail("timed out waiting for " + what)

    def send(self, msg, stamp):
        msg.header.stamp = rospy.Time(stamp, 0)
        self.pub.publish(msg)

    def test_each_bad_frame_is_rejected_and_the_next_good_one_processed(self):
        self.wait(lambda: self.pub.get_num_connections() > 0, "the nodelet to subscribe (lazily)")
        stamp, sent, rejected, processed = 1000, 0, 0, 0
        bad_stamps = []

        def good_frame():
            nonlocal stamp, sent, processed
            stamp += 1
            self.send(copy(self.good), stamp)
            sent += 1
            processed += 1
            s = stamp
            self.wait(lambda: s in self.outputs, "the labelled output of good frame %d" % s)
            self.assertEqual(self.outputs[s].width, self.good.width)

        good_frame()  # the nodelet is up and warm
        for name, corrupt, words in bad_cases(self.good):
            stamp += 1
            bad_stamps.append(stamp)
            self.send(corrupt(copy(self.good)), stamp)
            sent += 1
            rejected += 1
            n = rejected
            # the diagnostics (1 Hz) must count this rejection and name its problem
            self.wait(lambda: self.diag is not None and int(self.diag["frames rejected"]) == n,
                      "diagnostics to count rejection '%s'" % name)
            last = self.diag["last rejection"]
            rospy.loginfo("%-22s -> %s", name, last)
            self.assertTrue(any(w in last for w in words), "%s: '%s' names none of %s" % (name, last, words))
            self.assertEqual(self.diag_level, DiagnosticStatus.WARN)
            good_frame()

        for name, msg in legal_cases(self.good):
            stamp += 1
            self.send(msg, stamp)
            sent += 1
            processed += 1
            s = stamp
            self.wait(lambda: s in self.outputs, "the output of legal frame '%s'" % name, timeout=60)
            self.assertEqual(self.outputs[s].width, msg.width, name)
            self.assertEqual(len(self.outputs[s].data), self.outputs[s].row_step * self.outputs[s].height, name)
            good_frame()

        with self.lock:
            leaked = [s for s in bad_stamps if s in self.outputs]
        self.assertEqual(leaked, [], "rejected frames produced output")
        self.wait(lambda: int(self.diag["frames received"]) == sent and
                  int(self.diag["frames processed"]) == processed and
                  int(self.diag["frames rejected"]) == rejected,
                  "diagnostics totals received=%d processed=%d rejected=%d" % (sent, processed, rejected))


if __name__ == "__main__":
    rospy.init_node("malformed_nodelet_test")
    rostest.rosrun(PKG, "malformed_nodelet", MalformedThroughNodelet, sys.argv)
