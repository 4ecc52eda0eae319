"""A ROS node for tools/slam_benchmark's mix-stock-less-sharp front end: stock A-LOAM's less sharp
set, less the points to which ours gives one of the labels named, republished on A-LOAM's topic.
Each stock point is found in ours' labelled cloud of the same stamp by its coordinates (both are
the input's own floats).

  python3 less_sharp_relay.py STOCK_TOPIC LABELLED_TOPIC OUT_TOPIC [LABEL ...]   (0-4: none..rough)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.realpath(__file__))))


def xy_keys(a):
    """One integer per point from the bits of its x and y (float32): equal for the same point."""
    x = np.ascontiguousarray(a["x"], dtype=np.float32).view(np.uint32).astype(np.uint64)
    y = np.ascontiguousarray(a["y"], dtype=np.float32).view(np.uint32).astype(np.uint64)
    return x << np.uint64(32) | y


def kept(stock, labelled, drop):
    """Mask of the stock points to keep: those whose point in `labelled` has no label in `drop`
    (a point not found there is kept)."""
    keys = xy_keys(labelled)
    order = np.argsort(keys)
    want = xy_keys(stock)
    at = np.clip(np.searchsorted(keys[order], want), 0, len(keys) - 1)
    found = keys[order][at] == want
    return ~(found & np.isin(labelled["label"][order][at], drop))


def main(argv):
    import message_filters
    import rospy
    from sensor_msgs.msg import PointCloud2

    from rc_eval.cloud_io import read_cloud
    rospy.init_node("less_sharp_relay")
    argv = rospy.myargv(argv)
    stock_topic, labelled_topic, out_topic = argv[:3]
    drop = [int(v) for v in argv[3:]]
    pub = rospy.Publisher(out_topic, PointCloud2, queue_size=100)

    def relay(stock, labelled):
        keep = kept(read_cloud(stock), read_cloud(labelled), drop)
        out = PointCloud2(header=stock.header, height=1, width=int(keep.sum()), fields=stock.fields,
                          is_bigendian=stock.is_bigendian, point_step=stock.point_step, is_dense=True)
        out.row_step = out.point_step * out.width
        out.data = np.frombuffer(stock.data, np.uint8).reshape(-1, stock.point_step)[keep].tobytes()
        pub.publish(out)

    subs = [message_filters.Subscriber(t, PointCloud2) for t in (stock_topic, labelled_topic)]
    message_filters.TimeSynchronizer(subs, 20).registerCallback(relay)
    rospy.spin()


if __name__ == "__main__":
    main(sys.argv[1:])
