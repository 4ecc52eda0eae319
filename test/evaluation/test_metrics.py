#!/usr/bin/env python3
"""The unsupervised metrics on clouds whose answer is known: a noisy plane, pure and mixed
feature clusters, and a frame moved by a known transform."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "tools"))
from rc_eval.metrics import feature_purity, planarity, temporal_stability  # noqa: E402

DT = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("label", "u1"), ("primitive", "<i4")])


def cloud(p, label, prim=None):
    a = np.zeros(len(p), DT)
    a["x"], a["y"], a["z"] = p[:, 0], p[:, 1], p[:, 2]
    a["label"] = label
    a["primitive"] = -1 if prim is None else prim
    return a


class Metrics(unittest.TestCase):
    def test_planarity_is_reciprocal_error_in_cm(self):
        rng = np.random.default_rng(1)
        p = np.c_[rng.uniform(0, 5, (4000, 2)), np.zeros(4000)]
        p[:, 2] = rng.choice((-0.02, 0.02), 4000)  # every point exactly 2 cm off the plane
        score, err, n = planarity(cloud(p, 1, 0))
        self.assertEqual(n, 1)
        self.assertAlmostEqual(err, 0.02, delta=0.002)
        self.assertAlmostEqual(score, 0.5, delta=0.05)

    def test_purity(self):
        rng = np.random.default_rng(2)
        pure = rng.normal((0, 0, 0), 0.1, (40, 3))
        mixed = rng.normal((10, 0, 0), 0.1, (40, 3))
        lab = np.r_[np.full(40, 2), np.tile([2, 3], 20)]
        purity, n = feature_purity(cloud(np.r_[pure, mixed], lab))
        self.assertEqual(n, 2)
        self.assertAlmostEqual(purity, 0.5, places=6)  # entropies 0 and 1

    def test_stability_after_registration(self):
        rng = np.random.default_rng(3)
        # three walls and a floor: a registrable scene
        pts = []
        for axis, off in ((0, 8.0), (1, 6.0), (1, -7.0), (2, -1.5)):
            q = rng.uniform(-10, 10, (3000, 3))
            q[:, axis] = off
            pts.append(q)
        p = np.concatenate(pts)
        lab = (np.arange(len(p)) % 4 + 1).astype(np.uint8)
        yaw, t = 0.05, np.array([0.4, -0.2, 0.0])
        R = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
        moved = (p - t) @ R  # frame B sees the scene from a moved pose
        stab, matched, T = temporal_stability(cloud(p, lab), cloud(moved, lab))
        np.testing.assert_allclose(T[:3, :3], R, atol=1e-3)
        np.testing.assert_allclose(T[:3, 3], t, atol=1e-2)
        self.assertGreater(matched, 0.99)
        self.assertGreater(stab, 0.99)
        flipped = lab.copy()
        flipped[::2] = 4
        stab2, _, _ = temporal_stability(cloud(p, lab), cloud(moved, flipped))
        self.assertLess(stab2, 0.8)


if __name__ == "__main__":
    unittest.main()
