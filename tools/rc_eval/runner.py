"""Runs the package's own executables (process_bag, baseline_labels) on bags and reads back the
labelled clouds. The evaluation never re-implements the method: labels come from the same code
path as the nodelet."""
import os
import shutil
import subprocess
import tempfile
import time

from .cloud_io import read_bag_clouds

LABELLED_TOPIC = "/ring_curvature/labelled_points"
PRIMITIVES_TOPIC = "/ring_curvature/primitives"


def workspace_dir():
    """The catkin workspace scripts/build makes: RC_WS, default <repo>/.catkin_ws."""
    repo = os.path.realpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", ".."))
    return os.environ.get("RC_WS") or os.path.join(repo, ".catkin_ws")


def tool_command(name):
    """How to start one of the package's C++ tools: RC_BIN_DIR/<name> when set, else the first
    <prefix>/lib/ring_curvature/<name> on CMAKE_PREFIX_PATH (set by devel/setup.bash), else the
    one scripts/build made (RC_WS or <repo>/.catkin_ws), else rosrun. Not rosrun first: with
    catkin workspaces inside the package folder, rosrun finds the tool once per workspace and
    stops to ask which one to run."""
    bin_dir = os.environ.get("RC_BIN_DIR")
    if bin_dir:
        return [os.path.join(bin_dir, name)]
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        path = os.path.join(prefix, "lib", "ring_curvature", name)
        if prefix and os.access(path, os.X_OK):
            return [path]
    path = os.path.join(workspace_dir(), "devel", "lib", "ring_curvature", name)  # not sourced
    if os.access(path, os.X_OK):
        return [path]
    if shutil.which("rosrun") is None:
        raise RuntimeError("%s not found: build with scripts/build, or source the workspace (devel/setup.bash)" % name)
    return ["rosrun", "ring_curvature", name]


def write_params(path, params):
    with open(path, "w") as f:
        for k, v in params.items():
            f.write("%s: %s\n" % (k, str(v).lower() if isinstance(v, bool) else v))


def run_method(method, in_bag, out_bag, params=None, topic="/velodyne_points", times_csv=None):
    """Labels in_bag into out_bag with 'ours' (process_bag with params) or a baseline
    ('pca', 'euclid' via baseline_labels). Returns wall time [s] of the tool. times_csv (ours
    only): where process_bag writes its per-frame stage times."""
    if method == "ours":
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
            pfile = f.name
        write_params(pfile, params or {})
        cmd = tool_command("process_bag") + ["--input", in_bag, "--output", out_bag, "--topic", topic,
                                              "--params", pfile]
        if times_csv:
            cmd += ["--times-csv", times_csv]
    else:
        pfile = None
        cmd = tool_command("baseline_labels") + ["--input", in_bag, "--output", out_bag, "--method", method,
                                                  "--topic", topic]
    t0 = time.monotonic()
    try:
        res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    finally:
        if pfile:
            os.unlink(pfile)
    if res.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), res.returncode, res.stderr.strip()[-2000:]))
    return time.monotonic() - t0


def labelled_frames(out_bag):
    """Structured arrays of the labelled clouds, in bag order."""
    return [a for _, a, _ in read_bag_clouds(out_bag, LABELLED_TOPIC)]


def primitive_frames(out_bag):
    """PrimitiveArray messages in bag order ([] when the tool wrote none)."""
    import rosbag
    with rosbag.Bag(out_bag) as bag:
        return [m for _, m, _ in bag.read_messages(topics=[PRIMITIVES_TOPIC])]
