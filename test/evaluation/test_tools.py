#!/usr/bin/env python3
"""The report's measuring tools: process_bag --times-csv (Figure 7) writes one consistent row per
frame, and convergence_table (Figure 4) shows first order for the developed formula and a stall
for the paper's z-plane formula on the tilted ground (what test_convergence.cpp asserts)."""
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


class Tools(unittest.TestCase):
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
