#!/usr/bin/python3
"""The scorer against hand-counted cases: one-sample tolerance, runs, the seam, holes left by
no-returns, don't-care classes."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "tools"))
from rc_eval.scoring import rates, score  # noqa: E402

N = 100  # columns per ring


def ring_cloud(rings=1, offset_frac=0.3, missing=()):
    """Points on circles, clockwise like the sensor, column c of ring r at azimuth
    -(c + r * offset_frac) * 360 / N deg; `missing` columns are dropped (no-returns)."""
    cols, ring = np.meshgrid(np.arange(N), np.arange(rings))
    cols, ring = cols.ravel(), ring.ravel()
    keep = ~np.isin(cols, missing)
    cols, ring = cols[keep], ring[keep]
    az = -np.radians((cols + ring * offset_frac) * 360.0 / N)
    return cols, ring, 10 * np.cos(az), 10 * np.sin(az)


class RunScoring(unittest.TestCase):
    def run_case(self, gt_cols, pred_cols, gt_class=2, label=2, others=None, missing=()):
        cols, ring, x, y = ring_cloud(missing=missing)
        gt = np.ones(len(cols), np.uint8)
        lab = np.ones(len(cols), np.uint8)
        gt[np.isin(cols, gt_cols)] = gt_class
        lab[np.isin(cols, pred_cols)] = label
        for c, g in (others or {}).items():
            gt[cols == c] = g
        return score(lab, gt, ring, x, y)

    def test_found_within_one_sample(self):
        c = self.run_case([10, 11], [12])["Edge"]
        self.assertEqual((c["gt_tp"], c["gt_fn"], c["pred_tp"], c["pred_fp"]), (1, 0, 1, 0))

    def test_two_samples_away_is_missed_and_false(self):
        c = self.run_case([10, 11], [13])["Edge"]
        self.assertEqual((c["gt_tp"], c["gt_fn"], c["pred_tp"], c["pred_fp"]), (0, 1, 0, 1))
        self.assertEqual(rates(c), (0.0, 0.0))

    def test_runs_are_counted_once(self):
        # one gt run of 2 points, one predicted run of 3 points: one each, not per point
        c = self.run_case([40, 41], [39, 40, 41])["Edge"]
        self.assertEqual((c["gt_tp"], c["pred_tp"], c["pred_fp"]), (1, 1, 0))

    def test_seam_joins_a_run(self):
        c = self.run_case([99, 0], [1])["Edge"]
        self.assertEqual((c["gt_tp"], c["gt_fn"]), (1, 0))

    def test_no_return_hole_is_a_sample(self):
        # column 51 missing: 50 and 52 are two samples apart, not neighbours
        c = self.run_case([52], [50], missing=[51])["Edge"]
        self.assertEqual((c["gt_tp"], c["gt_fn"], c["pred_fp"]), (0, 1, 1))

    def test_corner_on_a_crease_is_wrong_type_but_a_feature(self):
        c = self.run_case([20, 21], [20], gt_class=2, label=3)
        self.assertEqual((c["Edge"]["gt_fn"], c["Corner"]["pred_fp"]), (1, 1))
        self.assertEqual((c["Feature"]["gt_tp"], c["Feature"]["pred_tp"]), (1, 1))

    def test_edge_on_curved_surface_is_false(self):
        c = self.run_case([], [30], others={29: 5, 30: 5, 31: 5})["Edge"]
        self.assertEqual(c["pred_fp"], 1)

    def test_edge_next_to_unknown_is_ignored(self):
        c = self.run_case([], [30], others={31: 0})["Edge"]
        self.assertEqual(c["pred_fp"], 0)

    def test_ring_offsets_do_not_merge_rings(self):
        cols, ring, x, y = ring_cloud(rings=3, offset_frac=0.45)
        gt = np.ones(len(cols), np.uint8)
        lab = np.ones(len(cols), np.uint8)
        gt[(ring == 0) & (cols == 5)] = 3
        lab[(ring == 1) & (cols == 5)] = 3  # same azimuth, other ring: not a hit
        c = score(lab, gt, ring, x, y)["Corner"]
        self.assertEqual((c["gt_tp"], c["gt_fn"], c["pred_fp"]), (0, 1, 1))


class JumpsAndThinObjects(unittest.TestCase):
    """Issue 29's definitions: only the near side of a depth jump is a Corner (the far side is
    the occluder's shadow), and a thin object is found by an Edge or a Corner."""

    def cloud(self, far_from=None):
        cols, ring, x, y = ring_cloud()
        if far_from is not None:  # columns >= far_from lie 5 m behind the others
            s = np.where(cols >= far_from, 1.5, 1.0)
            x, y = x * s, y * s
        return cols, ring, x, y

    def test_corner_on_the_far_side_only_is_false(self):
        cols, ring, x, y = self.cloud(far_from=21)
        gt = np.ones(len(cols), np.uint8)
        gt[cols == 20] = 3  # near side; 21 is its shadow (planar)
        for pred, expect in ((21, (0, 1, 0, 1)), (20, (1, 0, 1, 0)), (19, (1, 0, 1, 0))):
            lab = np.ones(len(cols), np.uint8)
            lab[cols == pred] = 3
            c = score(lab, gt, ring, x, y)["Corner"]
            self.assertEqual((c["gt_tp"], c["gt_fn"], c["pred_tp"], c["pred_fp"]), expect, pred)

    def test_same_range_neighbour_is_within_tolerance(self):
        # without a range step the one-sample tolerance holds on both sides, as before
        c = RunScoring().run_case([20], [21], gt_class=3, label=3)["Corner"]
        self.assertEqual((c["gt_tp"], c["pred_fp"]), (1, 0))

    def test_thin_found_by_edge_or_corner(self):
        cols, ring, x, y = self.cloud()
        gt = np.ones(len(cols), np.uint8)
        gt[np.isin(cols, [40, 41, 42])] = 6
        for label in (2, 3):
            lab = np.ones(len(cols), np.uint8)
            lab[cols == 41] = label
            c = score(lab, gt, ring, x, y)
            self.assertEqual((c["Thin"]["gt_tp"], c["Edge"]["gt_tp"], c["Feature"]["gt_tp"]), (1, 1, 1))
            name = "Edge" if label == 2 else "Corner"
            self.assertEqual((c[name]["pred_tp"], c[name]["pred_fp"]), (1, 0))
            self.assertEqual(c["Corner"]["gt_tp"] + c["Corner"]["gt_fn"], 0)  # thin is not Corner's
            self.assertEqual(rates(c["Thin"])[0], None)

    def test_plane_on_thin_is_wrong(self):
        cols, ring, x, y = self.cloud()
        gt = np.ones(len(cols), np.uint8)
        gt[np.isin(cols, [40, 41, 42])] = 6
        c = score(np.ones(len(cols), np.uint8), gt, ring, x, y)
        self.assertEqual((c["Plane"]["pred_fp"], c["Thin"]["gt_fn"], c["Edge"]["gt_fn"]), (3, 1, 1))


class PointScoring(unittest.TestCase):
    def test_plane_and_rough(self):
        cols, ring, x, y = ring_cloud()
        gt = np.array([1] * 50 + [4] * 30 + [5] * 20, np.uint8)
        lab = np.array([1] * 40 + [4] * 10 + [4] * 20 + [1] * 10 + [1] * 20, np.uint8)
        c = score(lab, gt, ring, x, y)
        # Plane: 40 right; 10 on vegetation wrong; 20 on curved don't-care; 10 planar missed
        self.assertEqual(rates(c["Plane"]), (40 / 50, 40 / 50))
        # Rough: 20 right of 30 predicted (10 on planar); 20 of 30 vegetation found
        self.assertEqual(rates(c["Rough"]), (20 / 30, 20 / 30))


if __name__ == "__main__":
    unittest.main()
