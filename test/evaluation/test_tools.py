#!/usr/bin/env python3
"""The report's measuring tools: process_bag --times-csv (Figure 7) writes one consistent row per
frame, convergence_table (Figure 4) shows first order for the developed formula and a stall
for the paper's z-plane formula on the tilted ground (what test_convergence.cpp asserts), and the
SLAM benchmark's two ATE definitions behave as documented."""
import importlib.machinery
import importlib.util
import os
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
from rc_eval.figures import STAGES, convergence_rows, read_times  # noqa: E402
from rc_eval.runner import labelled_frames, run_method  # noqa: E402


def slam_benchmark():
    path = os.path.join(ROOT, "tools", "slam_benchmark")
    loader = importlib.machinery.SourceFileLoader("slam_benchmark", path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader("slam_benchmark", loader))
    loader.exec_module(module)
    return module


class Tools(unittest.TestCase):
    def test_side_by_side_summary(self):
        from rc_eval.frontend_timing import WARM_UP, summarize
        stock = [100.0] * WARM_UP + [20.0, 10.0, 30.0, 40.0]
        ours = [1.0] * WARM_UP + [10.0, 10.0, 3.0, 20.0]  # per-frame ratios 0.5, 1.0, 0.1, 0.5
        row = summarize({}, {"stock": stock, "ours": ours}, stock[:-1], ours)
        self.assertAlmostEqual(row["cpu_ms_stock"], 25.0)  # the warm-up frames do not count
        self.assertAlmostEqual(row["cpu_ms_ours"], 10.0)
        self.assertAlmostEqual(row["cpu_ratio"], 0.5)  # the median of per-frame ratios, not 10 / 25
        self.assertAlmostEqual(row["cpu_ratio_p10"], 0.1)
        self.assertAlmostEqual(row["cpu_ratio_p90"], 0.5)
        # callbacks pair frame by frame up to the shorter list (stock's log may lack the last line)
        self.assertAlmostEqual(row["cb_ratio"], 0.5)
        self.assertAlmostEqual(row["cb_ms_stock"], 20.0)
        empty = summarize({}, {"stock": stock[:WARM_UP], "ours": ours[:WARM_UP]}, [], [])
        self.assertTrue(np.isnan(empty["cpu_ratio"]) and np.isnan(empty["cb_ms_ours"]))

    def test_slam_ate_definitions(self):
        sb = slam_benchmark()
        rng = np.random.default_rng(3)
        n = 50
        pos = np.cumsum(rng.normal(0.0, 0.5, (n, 3)), axis=0)
        gt = np.hstack([np.arange(n)[:, None] * 0.1, pos, np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))])
        c, s = np.cos(0.4), np.sin(0.4)
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        yaw = [0.0, 0.0, np.sin(0.2), np.cos(0.2)]  # the same 0.4 rad about z, as x, y, z, w
        # A rigidly moved copy: no error under either alignment.
        est = {gt[i, 0]: (R @ pos[i] + [3.0, -1.0, 2.0], yaw) for i in range(n)}
        ate, drift, m, ate_aligned = sb.trajectory_errors(gt, est)
        self.assertEqual(m, n)
        self.assertLess(ate, 1e-9)
        self.assertLess(ate_aligned, 1e-9)
        # An error in the first pose only: the first-pose ATE carries it through every frame, the
        # best-fit alignment spreads it and is the smaller.
        est = {gt[i, 0]: (pos[i] + (0.0 if i else 0.3), [0.0, 0.0, 0.0, 1.0]) for i in range(n)}
        ate, _, _, ate_aligned = sb.trajectory_errors(gt, est)
        self.assertAlmostEqual(ate, 0.3 * np.sqrt(3.0) * np.sqrt((n - 1) / n), places=6)  # all frames but the first
        self.assertLess(ate_aligned, ate / 3)
        # Noise: the best-fit ATE is the RMSE of the noise, within sampling error.
        noise = rng.normal(0.0, 0.05, (n, 3))
        est = {gt[i, 0]: (pos[i] + noise[i], [0.0, 0.0, 0.0, 1.0]) for i in range(n)}
        _, _, _, ate_aligned = sb.trajectory_errors(gt, est)
        self.assertLess(ate_aligned, np.sqrt(np.mean(np.sum(noise ** 2, axis=1))) + 1e-12)
        self.assertGreater(ate_aligned, 0.5 * 0.05 * np.sqrt(3.0))
        # Poses stamped half a frame later (ours, referred to the sweep's middle) are compared
        # with the ground truth there: an exact estimate has no error, one at the frame's own
        # stamp has the half step's, and the last one still counts (past the last row).
        mid = {gt[i, 0] + 0.05: (0.5 * (pos[i] + pos[min(i + 1, n - 1)]) if i + 1 < n
                                 else pos[i] + 0.5 * (pos[i] - pos[i - 1]), [0.0, 0.0, 0.0, 1.0]) for i in range(n)}
        ate, drift, m, ate_aligned = sb.trajectory_errors(gt, mid)
        self.assertEqual(m, n)
        self.assertLess(ate, 1e-9)
        self.assertLess(ate_aligned, 1e-9)
        late = {gt[i, 0] + 0.05: (pos[i], [0.0, 0.0, 0.0, 1.0]) for i in range(n)}
        ate, _, _, _ = sb.trajectory_errors(gt, late)
        self.assertGreater(ate, 0.1)  # half a step of 0.5 m per axis, less the first pose's share

    def test_real_label_evaluation_takes_an_organized_nan_padded_cloud(self):
        # an OS1-128-like frame as ouster-ros publishes it: no-returns NaN, kept in place; its
        # annotation as SemanticKITTI's .label files come, the instance in the upper 16 bits
        import rosbag
        import rospy
        from std_msgs.msg import Header
        from rc_eval import real_labels as rl
        from rc_eval.cloud_io import make_cloud
        from rc_eval.raycast import Box, Ground
        from rc_eval.sequence import OUSTER_LAYOUT, OUSTER_POINT_STEP, make_path, sensor_for, simulate_sequence_frame
        sensor = sensor_for("os128")
        scene = [(Ground(-1.8), None, np.inf), (Box((12.0, 0.0, 2.0), (1.0, 8.0, 4.0)), None, np.inf)]
        pts = simulate_sequence_frame(sensor, make_path("street", 6.0, 1.0), scene, 0, 0.0, np.random.default_rng(1))
        self.assertTrue(np.isnan(pts["z"]).any())
        sem = np.where(np.isnan(pts["z"]), 0, np.where(pts["z"] < -1.7, 40, 50)).astype(np.uint32)
        with tempfile.TemporaryDirectory() as d:
            bag = os.path.join(d, "organized.bag")
            msg = make_cloud(pts, OUSTER_LAYOUT, Header(stamp=rospy.Time(1.0), frame_id="os"), 128, 1024,
                             itemsize=OUSTER_POINT_STEP)
            with rosbag.Bag(bag, "w") as b:
                b.write(rl.TOPIC, msg, msg.header.stamp)
            np.save(os.path.join(d, "organized_sem.npy"), sem | np.uint32(7 << 16))  # a .label's instance bits
            res = rl.evaluate([bag], labellers=("defaults",))
        got = res["labellers"]["defaults"]
        self.assertNotIn("error", got)
        ground = got["all"]["ground_plane"]
        self.assertEqual(ground[1], int(np.count_nonzero(sem == 40)))  # every ground return, no NaN
        self.assertGreater(ground[0] / ground[1], 0.9)
        # the returns unorganized, their ring in a field of another name: read with sensor_params
        hit = np.isfinite(pts["z"])
        layout = [("x", 0, "<f4"), ("y", 4, "<f4"), ("z", 8, "<f4"), ("ring_index", 12, "<u2")]
        with tempfile.TemporaryDirectory() as d:
            bag = os.path.join(d, "unorganized.bag")
            fields = {"x": pts["x"][hit], "y": pts["y"][hit], "z": pts["z"][hit], "ring_index": pts["ring"][hit]}
            msg = make_cloud(fields, layout, Header(stamp=rospy.Time(1.0), frame_id="os"), 1, int(hit.sum()))
            with rosbag.Bag(bag, "w") as b:
                b.write(rl.TOPIC, msg, msg.header.stamp)
            np.save(os.path.join(d, "unorganized_sem.npy"), sem[hit])
            self.assertIn("error", rl.evaluate([bag], labellers=("defaults",))["labellers"]["defaults"])
            res = rl.evaluate([bag], labellers=("defaults",), sensor_params={"ring_field": "ring_index"})
        self.assertEqual(res["labellers"]["defaults"]["all"]["ground_plane"], ground)

    def test_evaluate_real_params_for_another_sensor(self):
        from rc_eval import real_labels as rl
        a = rl.parse(["--param", "ring_field=ring_index", "--param", "time_unit=ns"])
        self.assertEqual(a.param, {"ring_field": "ring_index", "time_unit": "ns"})
        with self.assertRaises(SystemExit):
            rl.parse(["--param", "ring_field"])

    def test_mixed_front_ends_split_the_sets_between_stock_and_ours(self):
        import xml.etree.ElementTree as ET
        from rc_eval.slam_frontends import mixed_command, mixed_launch

        def remaps(path):
            nodes = {n.get("name"): n for n in ET.parse(path).getroot().findall("node")}
            ours = nodes["ours_frontend"]
            deskew = [q.get("value") for q in ours.findall("param") if q.get("name") == "deskew_odometry"]
            self.assertEqual(deskew, ["/aft_mapped_to_init"] if "all-but" in path else [])  # as deskew below
            return [{r.get("from"): r.get("to") for r in n.findall("remap")} for n in (nodes["stock_frontend"], ours)]
        with tempfile.TemporaryDirectory() as d:
            stock, ours = remaps(mixed_launch("edges", None, False, d))
            self.assertEqual(ours["~loam/sharp"], "/laser_cloud_sharp")
            self.assertEqual(ours["~loam/less_sharp"], "/laser_cloud_less_sharp")
            self.assertTrue(ours["~loam/flat"].startswith("/unused/"))
            self.assertTrue(stock["/laser_cloud_sharp"].startswith("/unused/"))
            self.assertNotIn("/laser_cloud_flat", stock)  # stock's planes go to A-LOAM
            stock, ours = remaps(mixed_launch("all-but-less-sharp", None, True, d, ("rough",)))
            self.assertTrue(ours["~loam/less_sharp"].startswith("/unused/"))
            self.assertEqual(ours["~loam/cloud"], "/velodyne_cloud_2")
            # stock's less sharp set goes to the relay, which reads ours' labelled cloud
            self.assertEqual(stock["/laser_cloud_less_sharp"], "/unused/stock_less_sharp_all")
            self.assertEqual(ours["~labelled_points"], "/unused/ours_labelled")
            cmd = mixed_command("mix-stock-less-sharp", None, True, d, ("rough", "none"))
            self.assertEqual(cmd[:2], ["bash", "-c"])
            self.assertEqual(cmd[-4:], ["/unused/ours_labelled", "/laser_cloud_less_sharp", "4", "0"])

    def test_less_sharp_relay_drops_the_points_ours_labels_so(self):
        from rc_eval.less_sharp_relay import kept
        labelled = np.zeros(5, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("label", "u1")])
        labelled["x"], labelled["y"], labelled["label"] = [1, 2, 3, 4, 5], [0, 0, 1, 1, 0], [1, 4, 4, 2, 3]
        stock = np.zeros(4, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
        stock["x"], stock["y"] = [2, 3, 5, 9], [0, 1, 0, 9]  # Rough, Rough, Corner, not in ours' cloud
        self.assertEqual(list(kept(stock, labelled, [4])), [False, False, True, True])
        self.assertEqual(list(kept(stock, labelled, [3, 4])), [False, False, False, True])
        self.assertEqual(list(kept(stock, labelled, [])), [True] * 4)

    def test_label_cues_auc_and_bound(self):
        from rc_eval.label_cues import auc, fit_boosted, fit_logistic, grid_links
        self.assertEqual(auc(np.array([2.0, 3.0]), np.array([0.0, 1.0])), 1.0)
        self.assertEqual(auc(np.array([0.0]), np.array([1.0])), 0.0)
        self.assertEqual(auc(np.array([1.0, 1.0]), np.array([1.0])), 0.5)  # ties count half
        rng = np.random.default_rng(1)
        X = rng.normal(0.0, 1.0, (2000, 2))
        y = (X[:, 0] - 0.5 * X[:, 1] > 0).astype(float)  # separable by a line
        p = fit_logistic(X, y)(X)
        self.assertGreater(np.mean((p > 0.5) == (y > 0.5)), 0.97)
        # a box rule no line can draw: the trees learn it, with the gain on the two cues that matter
        X = rng.normal(0.0, 1.0, (4000, 3))
        y = ((np.abs(X[:, 0]) < 0.7) & (X[:, 1] > -0.3)).astype(float)
        boosted = fit_boosted(X[:3000], y[:3000], rounds=60)
        self.assertGreater(np.mean((boosted(X[3000:]) > 0.5) == (y[3000:] > 0.5)), 0.95)
        self.assertLess(np.mean((fit_logistic(X, y)(X) > 0.5) == (y > 0.5)), 0.85)
        self.assertLess(boosted.gain_share[2], 0.05)
        # the other frame's cues: a wall seen again from 1 m further on stays thin, a bush does not
        from rc_eval.label_cues import sequence_cues
        wall = np.stack([np.full(3000, 10.0), rng.uniform(-5, 5, 3000), rng.uniform(0, 3, 3000)], 1)
        bush = np.stack([rng.uniform(9.5, 10.5, 3000), rng.uniform(-5, 5, 3000), rng.uniform(0, 3, 3000)], 1)
        moved = np.eye(4)
        moved[0, 3] = 1.0  # frame 1 is 1 m ahead: its points are 1 m nearer in x
        for cloud, thin in ((wall, True), (bush, False)):
            other = cloud[rng.permutation(3000)] + rng.normal(0, 0.05, (3000, 3)) * [0, 1, 1]
            c = sequence_cues(cloud, 0, ([cloud, other - [1.0, 0.0, 0.0]], np.stack([np.eye(4), moved])))
            variation = np.median(c["other frame: surface variation of the neighbours"])
            self.assertEqual(variation < 1e-6, thin, variation)
            if thin:  # (on the plane only once moved by the poses: 1 m off it without)
                plane = np.exp(np.median(c["other frame: distance to the neighbours' plane / rho (log)"]))
                self.assertLess(plane, 1e-4)
        # two rings of four points: neighbours by azimuth, the ring above and below by azimuth
        az = np.tile([0.0, 0.5, 1.0, 1.5], 2)
        a = np.zeros(8, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("ring", "u2")])
        a["x"], a["y"], a["ring"] = np.cos(az), np.sin(az), np.repeat([0, 1], 4)
        prev, nxt, up, down = grid_links(a)
        self.assertEqual(list(nxt[:4]), [1, 2, 3, -1])
        self.assertEqual(list(prev[4:]), [-1, 4, 5, 6])
        self.assertEqual(list(up[:4]), [4, 5, 6, 7])
        self.assertEqual(list(down[4:]), [0, 1, 2, 3])
        self.assertEqual(list(down[:4]), [-1] * 4)

    def test_times_csv_has_one_row_per_frame_and_stages_sum_to_core(self):
        with tempfile.TemporaryDirectory() as d:
            out, csv = os.path.join(d, "l.bag"), os.path.join(d, "t.csv")
            run_method("ours", os.path.join(ROOT, "rosbag_fixtures", "synthetic_vlp16_street.bag"), out, {},
                       times_csv=csv)
            t = read_times(csv)
            frames = labelled_frames(out)
        self.assertEqual(len(t["core_ms"]), len(frames))
        self.assertTrue(np.all(t["core_ms"] > 0))
        np.testing.assert_allclose(sum(t[s] for s in STAGES), t["core_ms"], rtol=1e-3)
        self.assertEqual(list(t["points"]), [float(len(a)) for a in frames])

    def test_convergence_table_orders(self):
        rows, _ = convergence_rows()
        by = {}
        for r in rows:
            by.setdefault((r["shape"], r["formula"]), []).append(r)
        self.assertEqual(len(by), 4)
        for (shape, formula), rs in by.items():
            self.assertEqual([r["dtheta"] for r in rs], ["pi/32", "pi/64", "pi/128", "pi/256", "pi/512"])
            eoc = [float(r["eoc"]) for r in rs[1:]]
            if formula == "developed":
                for e in eoc:
                    self.assertTrue(0.9 <= e <= 1.1, "%s EOC %s" % (shape, eoc))
            else:  # converges to another quantity: the error stops shrinking
                self.assertLess(eoc[-1], 0.5, "%s %s EOC %s" % (shape, formula, eoc))


if __name__ == "__main__":
    unittest.main()
