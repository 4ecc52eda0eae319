"""PointCloud2 <-> numpy, by field name and datatype (never by position), and bag helpers."""
import numpy as np

# sensor_msgs/PointField datatypes
_NP = {1: "i1", 2: "u1", 3: "<i2", 4: "<u2", 5: "<i4", 6: "<u4", 7: "<f4", 8: "<f8"}
_CODE = {"i1": 1, "u1": 2, "<i2": 3, "<u2": 4, "<i4": 5, "<u4": 6, "<f4": 7, "<f8": 8}

# velodyne_pointcloud's packed XYZIRT layout, plus the simulator's ground truth at the end
XYZIRT_GT = [("x", 0, "<f4"), ("y", 4, "<f4"), ("z", 8, "<f4"), ("intensity", 12, "<f4"),
             ("ring", 16, "<u2"), ("time", 18, "<f4"), ("gt", 22, "u1")]


def cloud_dtype(msg):
    fields = [f for f in msg.fields if f.count >= 1]
    return np.dtype({"names": [f.name for f in fields], "formats": [_NP[f.datatype] for f in fields],
                     "offsets": [f.offset for f in fields], "itemsize": msg.point_step})


def read_cloud(msg):
    """Structured array of all points (row-major, organized clouds flattened)."""
    if msg.is_bigendian:
        raise ValueError("big-endian clouds are not supported")
    dt = cloud_dtype(msg)
    rows = [np.frombuffer(msg.data, dt, count=msg.width, offset=r * msg.row_step) for r in range(msg.height)]
    return np.concatenate(rows) if rows else np.zeros(0, dt)


def make_cloud(points, layout, header, height, width, itemsize=None):
    """PointCloud2 from a dict of arrays, packed with the given (name, offset, dtype) layout
    (records of `itemsize` bytes if given: a driver's padded point type)."""
    from sensor_msgs.msg import PointCloud2, PointField
    step = itemsize or max(off + np.dtype(t).itemsize for _, off, t in layout)
    dt = np.dtype({"names": [n for n, _, _ in layout], "formats": [t for _, _, t in layout],
                   "offsets": [o for _, o, _ in layout], "itemsize": step})
    arr = np.zeros(height * width, dt)
    for name, _, _ in layout:
        arr[name] = points[name]
    msg = PointCloud2()
    msg.header = header
    msg.height, msg.width = height, width
    msg.fields = [PointField(name=n, offset=o, datatype=_CODE[t], count=1) for n, o, t in layout]
    msg.is_bigendian = False
    msg.point_step = step
    msg.row_step = step * width
    msg.data = arr.tobytes()
    msg.is_dense = bool(np.all(np.isfinite(arr["x"])))
    return msg


def read_bag_clouds(path, topic):
    """[(stamp_seconds, structured array, msg)] for every PointCloud2 on topic."""
    import rosbag
    out = []
    with rosbag.Bag(path) as bag:
        for _, msg, _ in bag.read_messages(topics=[topic]):
            out.append((msg.header.stamp.to_sec(), read_cloud(msg), msg))
    return out


def bag_topics(path):
    import rosbag
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info()
    return {t: v.msg_type for t, v in info.topics.items()}
