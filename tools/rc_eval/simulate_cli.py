"""Command line of tools/simulate_scene."""
import argparse
import json
import os

import numpy as np

from .cloud_io import XYZIRT_GT, make_cloud
from .progress import Progress
from .scene import seed_vegetation, street_scene
from .sensors import SENSORS, make_sensor
from .simulate import GT_NAMES, gt_counts, simulate_frame, to_point_arrays


def parse(argv):
    p = argparse.ArgumentParser(prog="simulate_scene", description=__doc__)
    p.add_argument("--sensor", choices=SENSORS, default="vlp16")
    p.add_argument("--scene", choices=("street", "box"), default="street")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--frames", type=int, default=1)
    p.add_argument("--noise", type=float, default=0.0, help="range noise sigma [m]")
    p.add_argument("--dropout", type=float, default=0.0, help="probability of a no-return")
    p.add_argument("--velocity", type=float, nargs=3, default=(0.0, 0.0, 0.0),
                   help="sensor velocity during the sweeps [m/s], scene frame")
    p.add_argument("--yaw-rate", type=float, default=0.0, help="[rad/s]")
    p.add_argument("--height", type=float, default=1.8, help="sensor height above ground [m]")
    p.add_argument("--crease-min-angle", type=float, default=20.0,
                   help="folds between faces meeting at less than this [deg] are not creases")
    p.add_argument("--topic", default="/velodyne_points")
    p.add_argument("--frame-id", default="velodyne")
    p.add_argument("--output", required=True, help="bag to write")
    p.add_argument("--ground-truth", help="JSON sidecar (default: OUTPUT with .json)")
    return p.parse_args(argv)


def main(argv):
    import rosbag
    import rospy
    from std_msgs.msg import Header

    a = parse(argv)
    sensor = make_sensor(a.sensor)
    shapes = street_scene(a.seed, a.height, a.scene)
    sidecar = a.ground_truth or os.path.splitext(a.output)[0] + ".json"
    counts = {k: 0 for k in GT_NAMES.values()}
    prog = Progress(a.frames, "simulate")
    t0 = 1.6e9  # a fixed stamp keeps the bag byte-identical for a given seed
    with rosbag.Bag(a.output, "w") as bag:
        for k in range(a.frames):
            rng = np.random.default_rng([a.seed, k])
            seed_vegetation(shapes, np.random.default_rng([a.seed, k, 1]))
            frame = simulate_frame(sensor, shapes, k, a.noise, a.dropout, a.velocity, a.yaw_rate,
                                   a.crease_min_angle, rng)
            pts, (h, w) = to_point_arrays(sensor, frame)
            pts = {"x": pts["xyz"][:, 0], "y": pts["xyz"][:, 1], "z": pts["xyz"][:, 2],
                   "intensity": pts["intensity"], "ring": pts["ring"], "time": pts["time"], "gt": pts["gt"]}
            stamp = rospy.Time.from_sec(t0 + k * 60.0 / sensor.rpm)
            msg = make_cloud(pts, XYZIRT_GT, Header(seq=k, stamp=stamp, frame_id=a.frame_id), h, w)
            bag.write(a.topic, msg, stamp)
            for name, n in gt_counts(pts["gt"][np.isfinite(pts["x"])]).items():
                counts[name] += n
            prog.step("frame %d" % k)
    desc = {
        "generator": "tools/simulate_scene", "args": vars(a), "sensor": {
            "name": sensor.name, "beams": sensor.n_beams, "columns": sensor.n_columns,
            "azimuth_step_deg": sensor.azimuth_step_deg, "elevation_deg_firing_order": sensor.elevation_deg.tolist(),
            "organized": sensor.organized},
        "gt_classes": {str(k): v for k, v in GT_NAMES.items()},
        "gt_field": "gt", "gt_counts": counts, "shapes": [s.describe() for s in shapes]}
    with open(sidecar, "w") as f:
        json.dump(desc, f, indent=1)
    print("simulate_scene: %d frame(s) of %s to %s (%s); gt %s" % (
        a.frames, sensor.name, a.output, sidecar, ", ".join("%s %d" % kv for kv in counts.items())))
    return 0
