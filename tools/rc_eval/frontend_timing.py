"""tools/slam_benchmark --frontend side-by-side: the two front ends' time on the same frames,
measured side by side in one run so that the machine's drift cancels (as src/tools/ab_core.sh
does for two builds of the core). Both front ends are up throughout, each on an input topic of
its own, with every output subscribed; each frame goes to one of them, and once its five outputs
have arrived, to the other (stock first on even frames, ours first on odd ones). Per frame and
front end: CPU time of its process(es), all threads (schedstat, from the publish to the last
output's arrival), and its own callback time (ascanRegistration's printed TicToc, ours'
~frame_stats callback_ms). Ours deskews as in the benchmark, here with the ground-truth poses as
its odometry (A-LOAM's back end does not run). A sequence shorter than MIN_FRAMES (KITTI's 16) is
played again, its stamps moved on by its length each pass, until that many frames are timed: the
per-frame ratios of 14 frames spread too widely to tell 0.5 from 0.55.
With --callgrind both run under valgrind's callgrind, which counts the instructions each one's
callback executes (ascanRegistration's laserCloudHandler, ours' cloudCb, each with all it calls,
publishing included): a measure of the work that does not depend on the machine or its load."""
import copy
import glob
import os
import re
import statistics
import subprocess
import threading
import time

from rc_eval.slam_frontends import SWEEP_S, cpu_ns, frontend_command, frontend_pids

OUTPUTS = ("/velodyne_cloud_2", "/laser_cloud_sharp", "/laser_cloud_less_sharp", "/laser_cloud_flat",
           "/laser_cloud_less_flat")
WARM_UP = 2  # frames not counted: buffers grow, caches fill
MIN_FRAMES = 100  # frames timed per sequence at least (a shorter one is played again)


# The callbacks whose instructions --callgrind counts (valgrind --toggle-collect patterns).
CALLBACKS = {"stock": "laserCloudHandler*", "ours": "ring_curvature::RingCurvatureNodelet::cloudCb*"}


def callgrind_prefix(side, binary, out_dir):
    """valgrind's command line for the front end on `side` running `binary` ("stock" or "ours")."""
    return ("valgrind --tool=callgrind --dump-instr=no --toggle-collect=%s --callgrind-out-file=%s/%s.%%p"
            % (CALLBACKS[binary], out_dir, side))


def end_callgrind_runs(out_dir):
    """Kills what still runs under callgrind into out_dir (the counts are dumped by then): the
    nodelet manager outlives roslaunch's stop under valgrind, and would meet the next sequence's."""
    mark = ("--callgrind-out-file=" + out_dir + "/").encode()
    for _ in range(50):
        left = []
        for d in filter(str.isdigit, os.listdir("/proc")):
            try:
                with open("/proc/%s/cmdline" % d, "rb") as f:
                    if mark in f.read():
                        left.append(int(d))
            except OSError:
                pass
        if not left:
            return
        for pid in left:
            try:
                os.kill(pid, 9)
            except ProcessLookupError:
                pass
        time.sleep(0.2)


def instruction_counts(out_dir, frames):
    """Each side's instructions per frame in its callback: every callgrind run dumps its counts
    (callgrind_control -d), which are summed per side. NaN for a side without counts."""
    subprocess.run(["callgrind_control", "-d"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120)
    counts = {}
    for side in ("stock", "ours"):
        files, end = [], time.time() + 60.0
        while not files and time.time() < end:  # (the dump is written by the front end's process)
            time.sleep(0.5)
            files = glob.glob(os.path.join(out_dir, side + ".*.*"))
        total = 0
        for f in files:
            total += sum(int(m) for m in re.findall(r"^totals: ([0-9]+)", open(f).read(), re.M))
        counts["ir_" + side] = total / frames if files and frames else float("nan")
    return counts


def commands(deskew, params, reference, stub=False, callgrind=None):
    """Stock ascanRegistration and ours (launch/aloam_frontend.launch) on inputs of their own; both
    publish on A-LOAM's five topics (one at a time). With stub, "ours" is a second stock
    ascanRegistration: the null test of the measurement (ratios near 1). callgrind: a folder for
    the counts, both then run under callgrind."""
    prefix = {k: callgrind_prefix(k, "stock" if stub else k, callgrind) if callgrind else None for k in ("stock", "ours")}
    stock = frontend_command("stock", False, input_topic="/side_by_side/stock_points", prefix=prefix["stock"])
    ours = frontend_command("ours", stub, params, deskew, reference=reference, input_topic="/side_by_side/ours_points",
                            odometry="/side_by_side/odometry", prefix=prefix["ours"])
    return stock, ours + (["__name:=ours_stub"] if stub else [])


class Arrivals:
    """The outputs' stamps as they arrive, per front end (told apart by the publishing node)."""

    def __init__(self):
        import rospy
        from sensor_msgs.msg import PointCloud2
        self.seen = {"stock": {}, "ours": {}}  # front end -> topic -> last stamp
        self.changed = threading.Condition()  # waited on, not polled: the cores stay the front ends'
        self.subs = [rospy.Subscriber(t, PointCloud2, self._cloud, t, queue_size=10, buff_size=1 << 26)
                     for t in OUTPUTS]

    def _cloud(self, msg, topic):
        node = msg._connection_header.get("callerid", "")
        fe = "stock" if node.endswith("/scanRegistration") else "ours"
        with self.changed:
            self.seen[fe][topic] = msg.header.stamp.to_sec()
            self.changed.notify_all()

    def wait(self, fe, s, timeout):
        """Until all five outputs of the frame stamped s have arrived from fe; False on timeout."""
        with self.changed:
            return self.changed.wait_for(lambda: self.complete(fe, s), timeout)

    def complete(self, fe, s):
        """All five outputs of the frame stamped s (ours may stamp up to a sweep later)."""
        got = self.seen[fe]
        return all(t in got and s - 1e-6 <= got[t] < s + SWEEP_S for t in OUTPUTS)

    def close(self):
        for sub in self.subs:
            sub.unregister()


def odometry(row, frame_id="camera_init"):
    """A ground-truth TUM row as the nav_msgs/Odometry A-LOAM's mapping publishes."""
    import rospy
    from nav_msgs.msg import Odometry
    m = Odometry()
    m.header.stamp = rospy.Time.from_sec(row[0])
    m.header.frame_id = frame_id
    m.child_frame_id = "aft_mapped"
    p, q = m.pose.pose.position, m.pose.pose.orientation
    p.x, p.y, p.z = row[1:4]
    q.x, q.y, q.z, q.w = row[4:8]
    return m


def run(seq, bag, gt, deskew, procs, a, stats_recorder, stub=False):
    """One sequence side by side; the row of its figures."""
    import rosbag
    import rospy
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import PointCloud2

    row = {"sequence": seq, "frontend": "side-by-side(stub)" if stub else "side-by-side", "frames": 0}
    stats_recorder.reset()
    cg_dir = os.path.join(a.out, "callgrind", seq) if a.callgrind else None
    if cg_dir:
        os.makedirs(cg_dir, exist_ok=True)
        for f in glob.glob(os.path.join(cg_dir, "*")):
            os.remove(f)
    stock_cmd, ours_cmd = commands(deskew, a.ours_params, a.deskew_reference, stub, cg_dir)
    fe = {"stock": procs.start("%s_side_by_side_stock" % seq, stock_cmd),
          "ours": procs.start("%s_side_by_side_ours" % seq, ours_cmd)}
    pubs = {k: rospy.Publisher("/side_by_side/%s_points" % k, PointCloud2, queue_size=2) for k in fe}
    odom = rospy.Publisher("/side_by_side/odometry", Odometry, queue_size=10)
    arrivals = Arrivals()
    cpu = {"stock": [], "ours": []}
    try:
        def ready():
            return (all(p.get_num_connections() > 0 for p in pubs.values())
                    and (not deskew or stub or odom.get_num_connections() > 0)
                    and all(sub.get_num_connections() > 1 for sub in arrivals.subs))  # both publishers
        end = time.time() + (300.0 if cg_dir else 60.0)  # (under valgrind, start-up takes a while)
        timeout = max(a.timeout, 120.0) if cg_dir else a.timeout
        while not ready():
            if time.time() > end or any(p.poll() is not None for p in fe.values()):
                row["error"] = "front ends did not come up (logs in %s)" % a.out
                return row
            time.sleep(0.1)
        time.sleep(1.0)
        stats_recorder.watch_frame_stats()
        time.sleep(0.3)
        pids = {"stock": frontend_pids(fe["stock"].pid, "stock", False),
                "ours": frontend_pids(fe["ours"].pid, "ours", stub)}
        with rosbag.Bag(bag) as b:
            msgs = [m for _, m, _ in b.read_messages(topics=["/velodyne_points"])]
        limit = a.max_frames or max(MIN_FRAMES, len(msgs))
        period = (msgs[-1].header.stamp - msgs[0].header.stamp).to_sec() + SWEEP_S if msgs else 0.0
        for k in range(limit if msgs else 0):
            msg, shift = msgs[k % len(msgs)], (k // len(msgs)) * period
            if shift > 0:  # a later pass: the same clouds, later stamps (time goes forward)
                msg = copy.copy(msg)
                msg.header = copy.copy(msg.header)
                msg.header.stamp += rospy.Duration.from_sec(shift)
            s = msg.header.stamp.to_sec()
            if deskew and k % len(msgs) > 0:
                row_gt = list(gt[k % len(msgs) - 1])  # as A-LOAM's mapping would have, a frame back
                odom.publish(odometry([row_gt[0] + shift] + row_gt[1:]))
                time.sleep(0.002)
            order = ("stock", "ours") if k % 2 == 0 else ("ours", "stock")
            for name in order:
                c0 = cpu_ns(pids[name])
                pubs[name].publish(msg)
                if not arrivals.wait(name, s, timeout):
                    row["error"] = "%s gave no outputs of frame %d within %.0f s" % (name, k, timeout)
                    return row
                cpu[name].append((cpu_ns(pids[name]) - c0) / 1e6)
            row["frames"] += 1
        if cg_dir:
            row.update(instruction_counts(cg_dir, row["frames"]))
    finally:
        arrivals.close()
        stats_recorder.drop_stats()
        procs.stop(keep=1)  # the roscore stays
        if cg_dir:
            end_callgrind_runs(cg_dir)
    stock_cb = printed_times(os.path.join(a.out, "logs", "%s_side_by_side_stock.log" % seq))
    ours_cb = (printed_times(os.path.join(a.out, "logs", "%s_side_by_side_ours.log" % seq)) if stub
               else [v for _, v in sorted(stats_recorder.callback_ms.items())])
    return summarize(row, cpu, stock_cb, ours_cb)


def printed_times(log):
    """ascanRegistration's 'scan registration time X ms' per frame (printed once it has exited)."""
    try:
        return [float(m) for m in re.findall(r"scan registration time ([0-9.]+) ms", open(log).read())]
    except OSError:
        return []


def summarize(row, cpu, stock_cb, ours_cb):
    """Medians per front end over the frames after the warm-up, and ours over stock as the median
    and 10-90 % range of the per-frame ratios."""
    def ratios(a, b):
        r = sorted(x / y for x, y in zip(a[WARM_UP:], b[WARM_UP:]) if y > 0)
        if not r:
            return float("nan"), float("nan"), float("nan")
        return statistics.median(r), r[int(0.1 * (len(r) - 1))], r[int(0.9 * (len(r) - 1))]

    for name in ("stock", "ours"):
        row["cpu_ms_" + name] = statistics.median(cpu[name][WARM_UP:]) if len(cpu[name]) > WARM_UP else float("nan")
    row["cpu_ratio"], row["cpu_ratio_p10"], row["cpu_ratio_p90"] = ratios(cpu["ours"], cpu["stock"])
    n = min(len(stock_cb), len(ours_cb))
    row["cb_ms_stock"] = statistics.median(stock_cb[WARM_UP:n]) if n > WARM_UP else float("nan")
    row["cb_ms_ours"] = statistics.median(ours_cb[WARM_UP:n]) if n > WARM_UP else float("nan")
    row["cb_ratio"], row["cb_ratio_p10"], row["cb_ratio_p90"] = ratios(ours_cb[:n], stock_cb[:n])
    return row


def print_rows(rows):
    counted = [r for r in rows if "ir_ours" in r and not r.get("error")]
    if counted:  # (--callgrind: times under valgrind say nothing)
        print("%-14s %6s  %12s %12s  %s" % ("sequence", "frames", "stock [M]", "ours [M]", "ours/stock"))
        for r in rows:
            if r.get("error"):
                print("%-14s %6d  %s" % (r["sequence"], r["frames"], r["error"]))
                continue
            ratio = r["ir_ours"] / r["ir_stock"] if r["ir_stock"] > 0 else float("nan")  # (0: nothing counted)
            print("%-14s %6d  %12.1f %12.1f  %.3f" % (r["sequence"], r["frames"], r["ir_stock"] / 1e6,
                                                     r["ir_ours"] / 1e6, ratio))
        print("instructions per frame executed in each front end's callback, publishing included (callgrind; "
              "every frame,\nthe first ones too).")
        return
    print("%-14s %6s  %9s %9s  %-20s  %9s %9s  %-20s" % ("sequence", "frames", "stock cpu", "ours cpu",
                                                         "ours/stock [p10-p90]", "stock cb", "ours cb",
                                                         "ours/stock [p10-p90]"))
    for r in rows:
        if r.get("error"):
            print("%-14s %6d  %s" % (r["sequence"], r["frames"], r["error"]))
            continue
        print("%-14s %6d  %9.2f %9.2f  %.3f [%.3f-%.3f]   %9.2f %9.2f  %.3f [%.3f-%.3f]" % (
            r["sequence"], r["frames"], r["cpu_ms_stock"], r["cpu_ms_ours"], r["cpu_ratio"], r["cpu_ratio_p10"],
            r["cpu_ratio_p90"], r["cb_ms_stock"], r["cb_ms_ours"], r["cb_ratio"], r["cb_ratio_p10"],
            r["cb_ratio_p90"]))
    ok = [r for r in rows if not r.get("error")]
    if ok:
        gm = lambda xs: statistics.geometric_mean(xs)  # noqa: E731
        print("geometric mean of ours/stock: CPU %.3f, callback %.3f" % (
            gm([r["cpu_ratio"] for r in ok]), gm([r["cb_ratio"] for r in ok])))
    print("cpu: the front end's processes' CPU time per frame (all threads, publish to last output); "
          "cb: its own callback time\n(ascanRegistration's TicToc, ours' ~frame_stats callback_ms); medians after "
          "%d warm-up frames; ratios: median of the per-frame ratios." % WARM_UP)
