#!/usr/bin/python3
"""The simulator's ground truth against geometry computed here by hand, its point layout
against velodyne_pointcloud's, and its determinism."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "tools"))
from rc_eval.raycast import Box, Canopy, Cylinder, Ellipsoid, Hedge, rot_z  # noqa: E402
from rc_eval.scene import seed_vegetation, street_scene  # noqa: E402
from rc_eval.sensors import make_sensor  # noqa: E402
from rc_eval.simulate import simulate_frame, to_point_arrays  # noqa: E402


def run(shapes, sensor="vlp16", noise=0.0, dropout=0.0, seed=0, velocity=(0, 0, 0)):
    s = make_sensor(sensor)
    seed_vegetation(shapes, np.random.default_rng(seed + 1))
    return s, simulate_frame(s, shapes, 0, noise, dropout, velocity, 0.0, 20.0, np.random.default_rng(seed))


def azimuth_diff(a, b):
    return np.abs((a - b + 180.0) % 360.0 - 180.0)


class SequencePaths(unittest.TestCase):
    """The SLAM sequences' paths: at speed from the first frame, or from rest (street-hdl64-start),
    and ground truth that follows the path's arc length."""

    def test_from_rest_then_at_speed(self):
        from rc_eval.sequence import PRESETS, ground_truth_tum, make_path
        kind, _, speed, frames, accel = PRESETS["street-hdl64-start"]
        period = 0.1
        path = make_path(kind, speed, frames * period + 0.2, accel)
        t = np.array([0.0, 1.0, speed / accel, 5.0])
        np.testing.assert_allclose(path.distance(t), [0.0, 0.5 * accel, 0.5 * speed * speed / accel,
                                                     0.5 * speed * speed / accel + speed * (5.0 - speed / accel)])
        gt = np.array([list(map(float, line.split())) for line in
                       ground_truth_tum(path, frames, period, [k * period for k in range(frames)])])
        steps = np.linalg.norm(np.diff(gt[:, 1:3], axis=0), axis=1)
        self.assertLess(steps[0], 0.05)  # 1.5 cm in the first 0.1 s at 3 m/s^2
        self.assertGreater(steps[1], steps[0])
        np.testing.assert_allclose(steps[30:60], speed * period, rtol=0.02)  # at speed, straight on
        at_speed = make_path(kind, speed, frames * period + 0.2)
        np.testing.assert_allclose(at_speed.distance(t), speed * t)


    def test_organized_sensor_frames_as_ouster_ros_publishes_them(self):
        from rc_eval.raycast import Ground
        from rc_eval.sequence import make_path, sensor_for, simulate_sequence_frame
        sensor = sensor_for("os128")
        path = make_path("street", 6.0, 1.0)
        ground = [(Ground(-1.8), None, np.inf)]  # the ground 1.8 m below the sensor, nothing else
        rng = np.random.default_rng(1)
        pts = simulate_sequence_frame(sensor, path, ground, 0, 0.0, rng)
        self.assertEqual(len(pts["x"]), 128 * 1024)  # every column of every beam, hit or not
        rings = pts["ring"].reshape(128, 1024)
        np.testing.assert_array_equal(rings[:, 0], np.arange(128))
        hit = np.isfinite(pts["z"].reshape(128, 1024))
        self.assertFalse(hit[0].any())  # ring 0 is the top beam: it looks up, at nothing
        self.assertTrue(hit[-1].all())  # the bottom beam sees the ground all around
        self.assertTrue(np.all(pts["range"].reshape(128, 1024)[~hit] == 0))
        t = pts["t"].reshape(128, 1024)  # ns after the stamp, one time per column
        np.testing.assert_array_equal(t[0], t[-1])
        self.assertEqual(t[0, 0], 0)
        self.assertAlmostEqual(t[0, -1], 1023 * 1e9 * 0.1 / 1024, delta=1)


class GroundTruthGeometry(unittest.TestCase):
    """A tall box turned 45 deg in front of a wall: the ring crosses one vertical fold (the
    box's front edge, azimuth 0) and two silhouettes (its side edges); nothing else."""

    def setUp(self):
        self.box = Box((10.0, 0.0, 0.0), (1.5, 1.5, 20.0), rot_z(np.pi / 4))
        wall = Box((30.0, 0.0, 0.0), (1.0, 60.0, 20.0))
        self.sensor, self.f = run([self.box, wall])
        self.az = np.degrees(np.arctan2(self.f["xyz"][..., 1], self.f["xyz"][..., 0]))
        self.step = self.sensor.azimuth_step_deg

    def test_crease_flanks_the_front_edge(self):
        # front edge at (10 - 1.5 sqrt 2, 0): azimuth 0
        for b in range(self.sensor.n_beams):
            a = self.az[b][self.f["gt"][b] == 2]
            self.assertEqual(len(a), 2, "beam %d" % b)
            self.assertTrue(np.all(azimuth_diff(a, 0.0) < self.step), (b, a))

    def test_jumps_mark_the_near_side_of_the_silhouettes(self):
        # side corners at (10, +-1.5 sqrt 2): silhouettes at +-atan2(2.1213, 10); the jump sample
        # is the box's (near) one, the wall's sample beside it (the shadow) stays planar
        sil = np.degrees(np.arctan2(1.5 * np.sqrt(2), 10.0))
        for b in range(self.sensor.n_beams):
            jump = self.f["gt"][b] == 3
            a = self.az[b][jump]
            self.assertEqual(len(a), 2, "beam %d" % b)
            near = np.minimum(azimuth_diff(a, sil), azimuth_diff(a, -sil))
            self.assertTrue(np.all(near < self.step), (b, a))
            self.assertTrue(np.all(self.f["xyz"][b][jump][:, 0] < 11.0), b)  # on the box
            for c in np.nonzero(jump)[0]:
                far = [k % len(jump) for k in (c - 1, c + 1) if self.f["xyz"][b][k % len(jump), 0] > 25.0]
                self.assertEqual(len(far), 1, (b, c))
                self.assertEqual(self.f["gt"][b][far[0]], 1, (b, c))

    def test_everything_else_is_planar(self):
        g = self.f["gt"][self.f["valid"]]
        self.assertTrue(np.all(np.isin(g, (1, 2, 3))))
        self.assertGreater(np.mean(g == 1), 0.95)

    def test_ranges_are_exact_without_noise(self):
        # points on the wall's face x = 29
        wall = np.abs(self.az) > 20
        x = self.f["xyz"][..., 0][wall & self.f["valid"]]
        np.testing.assert_allclose(x, 29.0, atol=1e-6)


class SurfaceKinds(unittest.TestCase):
    def test_pole_is_thin_and_crown_is_vegetation(self):
        pole = Cylinder(8.0, 0.0, 0.3, -5.0, 5.0)
        crown = Ellipsoid((0.0, 8.0, 0.0), (2.0, 2.0, 3.0), density=3.0, role="tree_crown")
        s, f = run([pole, crown])
        az = np.degrees(np.arctan2(f["xyz"][..., 1], f["xyz"][..., 0]))
        v = f["valid"]
        pole_pts = v & (azimuth_diff(az, 0.0) < 1.0)
        crown_pts = v & (azimuth_diff(az, 90.0) < 10.0)
        self.assertTrue(np.all(f["gt"][pole_pts] == 6))  # every sample of a thin object
        self.assertGreater(np.sum(f["gt"][pole_pts] == 6), 20)
        self.assertTrue(np.all(f["gt"][crown_pts] == 4))
        r = np.linalg.norm(f["xyz"][crown_pts], axis=1)
        self.assertGreater(np.std(r), 0.2)  # returns scatter through the volume

    def test_thin_pole_before_a_wall_and_a_wide_cylinder(self):
        # a 0.2 m pole 8 m ahead before a wall: all its samples thin, its silhouettes too, the
        # wall's samples beside it (shadow) planar; a 1.2 m wide cylinder is curved, not thin
        pole = Cylinder(8.0, 0.0, 0.1, -5.0, 5.0)
        drum = Cylinder(0.0, 8.0, 0.6, -5.0, 5.0)
        wall = Box((20.0, 0.0, 0.0), (1.0, 60.0, 20.0))
        s, f = run([pole, drum, wall])
        az = np.degrees(np.arctan2(f["xyz"][..., 1], f["xyz"][..., 0]))
        x = f["xyz"][..., 0]
        v = f["valid"]
        on_pole = v & (x < 9.0) & (azimuth_diff(az, 0.0) < 2.0)
        self.assertTrue(np.all(f["gt"][on_pole] == 6))
        beside = v & (x > 18.0) & (azimuth_diff(az, 0.0) < 2.0)
        self.assertTrue(np.all(f["gt"][beside] == 1))
        drum_pts = v & (azimuth_diff(az, 90.0) < 2.0)
        self.assertTrue(np.all(np.isin(f["gt"][drum_pts], (3, 5))))
        self.assertGreater(np.sum(f["gt"][drum_pts] == 5), 20)

    def test_sign_plate_is_thin(self):
        plate = Box((10.0, 0.0, 0.5), (0.3, 0.015, 0.3), rot_z(0.3), role="sign_plate", thin=True)
        s, f = run([plate])
        g = f["gt"][f["valid"]]
        self.assertGreater(len(g), 3)
        self.assertTrue(np.all(g == 6))

    def test_canopy_returns_from_inside_with_gaps(self):
        env = (2.0, 2.0, 1.8)
        crown = Canopy((10.0, 0.0, 0.0), env, np.random.default_rng(4), clump_radius=0.35, cover=2.0, density=6.0)
        wall = Box((20.0, 0.0, 0.0), (1.0, 60.0, 20.0))
        s, f = run([crown, wall])
        az = np.degrees(np.arctan2(f["xyz"][..., 1], f["xyz"][..., 0]))
        v = f["valid"]
        ahead = v & (azimuth_diff(az, 0.0) < 5.0) & (np.abs(f["xyz"][..., 2]) < 1.0)
        r = np.linalg.norm(f["xyz"][ahead], axis=1)
        veg = f["gt"][ahead] == 4
        self.assertGreater(np.mean(veg), 0.5)
        self.assertGreater(np.mean(r[~veg] > 18.0), 0.9)  # the rest: the wall, through gaps
        self.assertGreater(np.sum(~veg), 5)
        depth = r[veg] - 8.0  # below the crown's front at x = 8
        self.assertGreater(np.percentile(depth, 90) - np.percentile(depth, 10), 0.3)  # tens of cm
        self.assertTrue(np.all((r[veg] > 7.9) & (r[veg] < 12.1)))

    def test_hedge_returns_inside_the_box(self):
        hedge = Hedge((8.0, 0.0, -1.0), (0.4, 4.0, 0.8), density=10.0)
        s, f = run([hedge])
        g, p = f["gt"][f["valid"]], f["xyz"][f["valid"]]
        self.assertTrue(np.all(g == 4))
        self.assertGreater(len(g), 50)
        self.assertTrue(np.all((p[:, 0] > 7.55) & (p[:, 0] < 8.45)))
        self.assertGreater(np.std(p[:, 0] - 7.6), 0.05)


class Layout(unittest.TestCase):
    def test_vlp16_firing_order_and_times(self):
        s = make_sensor("vlp16")
        np.testing.assert_array_equal(s.elevation_deg[:4], [-15, 1, -13, 3])
        np.testing.assert_array_equal(s.ring[:4], [0, 8, 1, 9])
        wall = Box((0.0, 0.0, 0.0), (30.0, 30.0, 50.0))  # sensor inside a closed room: all return
        _, f = run([wall])
        pts, (h, w) = to_point_arrays(s, f)
        self.assertEqual(h, 1)
        self.assertEqual(w, 16 * s.n_columns)
        np.testing.assert_array_equal(pts["ring"][:4], [0, 8, 1, 9])
        np.testing.assert_allclose(pts["time"][:3], [0.0, 2.304e-6, 4.608e-6])
        np.testing.assert_allclose(pts["time"][16], 55.296e-6)
        az = np.degrees(np.arctan2(pts["xyz"][:, 1], pts["xyz"][:, 0]))
        self.assertLess(((az[16] - az[0] + 180) % 360) - 180, 0)  # clockwise

    def test_os128_is_organized_with_nan(self):
        s = make_sensor("os128")
        _, f = run([Box((10.0, 0.0, 0.0), (1.0, 5.0, 2.0))], sensor="os128")
        pts, (h, w) = to_point_arrays(s, f)
        self.assertEqual((h, w), (128, 1024))
        self.assertEqual(len(pts["xyz"]), 128 * 1024)
        nan = ~np.isfinite(pts["xyz"][:, 0])
        self.assertTrue(nan.any() and (~nan).any())
        self.assertTrue(np.all(pts["gt"][nan] == 0))
        np.testing.assert_array_equal(pts["ring"].reshape(h, w)[:, 0], np.arange(128))

    def test_deterministic_from_seed(self):
        a = run(street_scene(7), noise=0.02, dropout=0.01, seed=3)[1]
        b = run(street_scene(7), noise=0.02, dropout=0.01, seed=3)[1]
        c = run(street_scene(8), noise=0.02, dropout=0.01, seed=3)[1]
        np.testing.assert_array_equal(a["gt"], b["gt"])
        np.testing.assert_array_equal(np.nan_to_num(a["xyz"]), np.nan_to_num(b["xyz"]))
        self.assertFalse(np.array_equal(a["gt"], c["gt"]))

    def test_noise_level(self):
        wall = Box((0.0, 0.0, 0.0), (30.0, 30.0, 50.0))
        clean = run([wall])[1]
        noisy = run([wall], noise=0.02, seed=5)[1]
        d = np.linalg.norm(noisy["xyz"], axis=-1) - np.linalg.norm(clean["xyz"], axis=-1)
        self.assertAlmostEqual(float(np.std(d)), 0.02, delta=0.001)

    def test_motion_skews_the_sweep(self):
        # room walls at x = +-30: a sensor moving at 10 m/s along +x sees the +x wall at
        # (30 - 10 t) / dx for a ray fired at time t with direction x-component dx
        wall = Box((0.0, 0.0, 0.0), (30.0, 30.0, 50.0))
        _, f = run([wall], velocity=(10.0, 0, 0))
        p = f["xyz"]
        r = np.linalg.norm(p, axis=-1)
        dx = p[..., 0] / r
        front = (dx > 0.5) & (np.abs(p[..., 1] / r / dx) * 30 < 25) & (np.abs(p[..., 2]) < 20)
        expected = (30.0 - 10.0 * f["time"][front]) / dx[front]
        np.testing.assert_allclose(r[front], expected, rtol=1e-9, atol=1e-6)
        self.assertGreater(np.ptp(f["time"][front]), 0.015)  # ~80 deg of sweep

if __name__ == "__main__":
    unittest.main()
