"""Simulated evaluation sets: one bag per noise level holding several scenes (street scenes from
consecutive seeds and one box scene), built with tools/simulate_scene's own code."""
import hashlib
import os

from .simulate_cli import main as simulate

TOPIC = "/velodyne_points"


def merge_bags(parts, out):
    """One bag with the clouds of all parts, restamped 0.1 s apart so frames stay ordered."""
    import rosbag
    import rospy
    k = 0
    with rosbag.Bag(out, "w") as dst:
        for p in parts:
            with rosbag.Bag(p) as src:
                for _, msg, _ in src.read_messages(topics=[TOPIC]):
                    msg.header.stamp = rospy.Time.from_sec(1.6e9 + 0.1 * k)
                    msg.header.seq = k
                    dst.write(TOPIC, msg, msg.header.stamp)
                    k += 1
    return out


def simulator_key():
    """Short hash of the simulator's sources: bags simulated by another version are not reused."""
    h = hashlib.sha1()
    here = os.path.dirname(os.path.realpath(__file__))
    for name in ("raycast.py", "scene.py", "sensors.py", "simulate.py", "simulate_cli.py"):
        with open(os.path.join(here, name), "rb") as f:
            h.update(f.read())
    return h.hexdigest()[:8]


def noise_sets(work_dir, noises, seeds, sensor="vlp16", dropout=0.005, quiet=True):
    """{noise: bag path}; reuses bags already in work_dir (they are deterministic) when the same
    simulator, seeds and dropout made them."""
    os.makedirs(work_dir, exist_ok=True)
    out = {}
    key = "%s_s%s_d%g" % (simulator_key(), "-".join(map(str, seeds)), dropout)
    for n in noises:
        path = os.path.join(work_dir, "%s_noise%03dmm_%s.bag" % (sensor, round(n * 1000), key))
        if not os.path.exists(path):
            parts = []
            for i, s in enumerate(list(seeds) + ["box"]):
                part = os.path.join(work_dir, "part_%d.bag" % i)
                scene = ["--scene", "box", "--seed", str(seeds[0] + 100)] if s == "box" else ["--seed", str(s)]
                args = ["--sensor", sensor, "--noise", str(n), "--dropout", str(dropout), "--output", part] + scene
                if quiet:
                    import contextlib
                    import io
                    with contextlib.redirect_stdout(io.StringIO()):
                        simulate(args)
                else:
                    simulate(args)
                parts.append(part)
            merge_bags(parts, path)
            for p in parts:
                os.unlink(p)
                os.unlink(os.path.splitext(p)[0] + ".json")
        out[n] = path
    return out
