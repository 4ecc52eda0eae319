#!/usr/bin/python3
"""Accuracy of the core's default parameters on the shipped synthetic fixtures, held above
floors a little below what it measured when the floors were set (accuracy_floors.json). Labels
come from process_bag, the nodelet's code path.

Re-measure (after a deliberate change of defaults, then lower/raise the floors by hand):
  test/evaluation/test_accuracy_regression.py --measure
"""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
from rc_eval.accuracy import score_bag, summary  # noqa: E402
from rc_eval.runner import run_method  # noqa: E402

FLOORS = os.path.join(HERE, "accuracy_floors.json")


def measure(fixture):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "labelled.bag")
        run_method("ours", os.path.join(ROOT, "rosbag_fixtures", fixture), out, {})
        return summary(score_bag(out))


class DefaultAccuracy(unittest.TestCase):
    pass


def _make(fixture, floors):
    def test(self):
        got = measure(fixture)
        low = []
        for cls, f in floors.items():
            p, r = got[cls]
            for what, value, floor in (("precision", p, f.get("precision")), ("recall", r, f.get("recall"))):
                if floor is not None and (value is None or value < floor):
                    low.append("%s %s %s < floor %.2f" % (cls, what, "n/a" if value is None else "%.3f" % value, floor))
        self.assertFalse(low, "%s: %s" % (fixture, "; ".join(low)))
    return test


with open(FLOORS) as fh:
    for _fixture, _floors in json.load(fh)["floors"].items():
        setattr(DefaultAccuracy, "test_" + os.path.splitext(_fixture)[0], _make(_fixture, _floors))

if __name__ == "__main__":
    if "--measure" in sys.argv:
        with open(FLOORS) as fh:
            for fx in json.load(fh)["floors"]:
                print(fx, json.dumps({k: ["%.3f" % v if v is not None else None for v in pr]
                                      for k, pr in measure(fx).items()}))
        sys.exit(0)
    unittest.main()
