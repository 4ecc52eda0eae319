"""The front ends tools/slam_benchmark runs before A-LOAM's odometry and mapping: stock
ascanRegistration, ours (launch/aloam_frontend.launch), or for diagnosis both at once with the
sets split between them; and the processes whose CPU time counts as the front end's."""
import os
import shlex
import sys

REPO = os.path.realpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", ".."))
OURS_LAUNCH = os.path.join(REPO, "launch", "aloam_frontend.launch")
# Diagnostic front ends: both run on every frame, A-LOAM gets one's edge sets (sharp, less sharp)
# and the other's plane sets (flat, less flat) and full cloud; which of ours' sets makes a difference.
MIXED = {"mix-ours-edges": "edges", "mix-ours-planes": "planes", "mix-stock-less-sharp": "all-but-less-sharp"}
LABELS = ("none", "plane", "edge", "corner", "rough")  # ours' label values 0-4
SWEEP_S = 0.1  # every sequence's sensor turns at 10 Hz

def mixed_command(name, params, deskew, out, without):
    """The command of a mixed front end: its launch file, and for mix-stock-less-sharp with labels
    to leave out, the relay that takes them out of stock's less sharp set."""
    launch = ["roslaunch", "--wait", mixed_launch(MIXED[name], params, deskew, out, without)]
    if not without:
        return launch
    relay = [sys.executable, os.path.join(REPO, "tools", "rc_eval", "less_sharp_relay.py"),
             "/unused/stock_less_sharp_all", "/unused/ours_labelled", "/laser_cloud_less_sharp"]
    relay += [str(LABELS.index(w)) for w in without]

    return ["bash", "-c", '"$@" & exec ' + " ".join(map(shlex.quote, launch)), "relay"] + relay


def mixed_launch(ours_sets, params, deskew, out, without=()):
    """A launch file (written to out) of stock ascanRegistration and ours side by side on
    /velodyne_points; ours publishes its `ours_sets` ("edges": sharp and less sharp; "planes":
    flat, less flat and the full cloud; "all-but-less-sharp") on A-LOAM's topics, stock the
    others (its less sharp set to the relay when labels are to be left `without`). Ours as
    launch/aloam_frontend.launch starts it, but deskewed to the stamp: A-LOAM pairs the sets by
    their stamps, and stock's are the input's."""
    ours_topics = {"edges": ("sharp", "less_sharp"), "planes": ("cloud", "flat", "less_flat"),
                   "all-but-less-sharp": ("cloud", "sharp", "flat", "less_flat")}[ours_sets]
    aloam = {"cloud": "/velodyne_cloud_2", "sharp": "/laser_cloud_sharp", "less_sharp": "/laser_cloud_less_sharp",
             "flat": "/laser_cloud_flat", "less_flat": "/laser_cloud_less_flat"}
    stock = "".join('    <remap from="%s" to="/unused/stock_%s"/>\n' % (aloam[t], t) for t in ours_topics)
    ours = "".join('    <remap from="~loam/%s" to="%s"/>\n' % (t, aloam[t] if t in ours_topics else "/unused/ours_" + t)
                   for t in aloam)
    if without:  # stock's less sharp goes through the relay (mixed_command), which reads ours' labels
        stock += '    <remap from="/laser_cloud_less_sharp" to="/unused/stock_less_sharp_all"/>\n'
        ours += '    <remap from="~labelled_points" to="/unused/ours_labelled"/>\n'
    text = """<launch>
  <node pkg="aloam_velodyne" type="ascanRegistration" name="stock_frontend" output="screen">
%s  </node>
  <node pkg="nodelet" type="nodelet" name="ours_manager" args="manager" output="screen"/>
  <node pkg="nodelet" type="nodelet" name="ours_frontend" args="load ring_curvature/RingCurvatureNodelet ours_manager"
        output="screen">
    <remap from="velodyne_points" to="/velodyne_points"/>
    <rosparam command="load" file="%s"/>
    <param name="scan_period" value="0.1"/>
    <param name="loam_point_format" value="xyzi"/>
    <param name="queue_size" value="2"/>
    <param name="deskew_reference" value="stamp"/>
%s%s  </node>
</launch>
""" % (stock, os.path.abspath(params) if params else os.path.join(REPO, "config", "ring_curvature.yaml"),
       '    <param name="deskew_odometry" value="/aft_mapped_to_init"/>\n' if deskew else "", ours)
    path = os.path.join(out, "mix_ours_%s.launch" % ours_sets)
    with open(path, "w") as f:
        f.write(text)
    return path


def frontend_command(name, stub, params=None, deskew=True, out=".", without=(), reference="middle",
                     input_topic="/velodyne_points", odometry=None, prefix=None):
    """The front end's command line. "ours" is ring_curvature's A-LOAM front end; this is the one
    place to change if launch/aloam_frontend.launch's arguments change. With stub (development
    only) "ours" runs stock ascanRegistration through the same code path. deskew: with A-LOAM's
    mapped pose (the launch's default; or the `odometry` topic), to the sweep's middle or its
    stamp (reference); off for scans the dataset has motion-compensated. prefix: a command line the
    front end's process runs under (valgrind ...): ascanRegistration's, or ours' nodelet manager's."""
    if name in MIXED:
        return mixed_command(name, params, deskew, out, without)
    if name == "stock" or stub:
        return (["rosrun"] + (["--prefix", prefix] if prefix else [])
                + ["aloam_velodyne", "ascanRegistration", "/velodyne_points:=" + input_topic])
    cmd = ["roslaunch", "--wait", "ring_curvature", "aloam_frontend.launch", "input:=" + input_topic]
    cmd += ["launch_prefix:=" + prefix] if prefix else []
    cmd += ["deskew_reference:=" + reference] if deskew else ["deskew:=false"]
    cmd += ["deskew_odometry:=" + odometry] if deskew and odometry else []
    return cmd + (["params:=" + os.path.abspath(params)] if params else [])


def label(name, stub):
    return "ours(stub)" if name == "ours" and stub else name


def descendants(root):
    """root and every process below it (by parent pid): roslaunch puts the nodes it starts in
    sessions of their own, so the process group is not enough."""
    parent = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open("/proc/%s/stat" % d) as f:
                    parent[int(d)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    out, todo = [], [root]
    while todo:
        p = todo.pop()
        out.append(p)
        todo.extend(c for c, pp in parent.items() if pp == p)
    return out


def cpu_ns(pids):
    """CPU time [ns] of every thread of the processes (schedstat: ns precision)."""
    total = 0
    for pid in pids:
        try:
            for t in os.listdir("/proc/%d/task" % pid):
                with open("/proc/%d/task/%s/schedstat" % (pid, t)) as f:
                    total += int(f.read().split()[0])
        except (OSError, ValueError):
            pass
    return total


def frontend_pids(root, name, stub):
    """The processes doing the front end's work: ascanRegistration, or for ours the
    nodelet manager(s) roslaunch started (not roslaunch itself)."""
    pids = []
    for pid in descendants(root):
        try:
            with open("/proc/%d/cmdline" % pid, "rb") as f:
                cmd = f.read().split(b"\0")
        except OSError:
            continue
        exe = os.path.basename(cmd[0].decode()) if cmd and cmd[0] else ""
        if name == "stock" or stub:
            if exe == "ascanRegistration":
                pids.append(pid)
        elif exe not in ("roslaunch", "python3", "bash", "sh", "rosmaster", "rosout"):
            pids.append(pid)  # (a mixed front end: both)
    return pids
