#!/usr/bin/python3
"""The defaults' labels on the human-annotated real frames (issue 29's rows, tools/rc_eval/
real_labels.py, all frames pooled), held within the bounds of real_label_floors.json: a floor a
little below today's value on each higher-is-better row, a ceiling a little above it on Edge/Corner
on vegetation. Labels come from process_bag, the nodelet's code path. Skipped where the shared
frames are absent (a user's clone has none): ../shared beside the repository, or RC_SHARED.

Re-measure (after a deliberate change, then move the bounds by hand):
  test/evaluation/test_real_labels_regression.py --measure
"""
import json
import os
import sys
import unittest

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools"))
from rc_eval import real_labels  # noqa: E402

BOUNDS = os.path.join(HERE, "real_label_floors.json")


def load():
    with open(BOUNDS) as f:
        return json.load(f)


def measure(spec):
    """{row: pooled value} of spec's labeller on spec's frames, or None when a frame is absent."""
    data = real_labels.default_data_dir()
    have = {os.path.basename(b): b for b in real_labels.labelled_bags(data)}
    if not all(f in have for f in spec["frames"]):
        return None
    res = real_labels.evaluate([have[f] for f in spec["frames"]], [spec["labeller"]])
    err = res["labellers"][spec["labeller"]].get("error")
    if err:
        raise RuntimeError(err)
    return real_labels.values(res, spec["labeller"])


def out_of_bounds(got, bounds):
    """['row value < min' ...] for every row outside its bounds (a row without a value fails)."""
    bad = []
    for row, b in bounds.items():
        v = got.get(row)
        if v is None:
            bad.append("%s: no value" % row)
        elif "min" in b and v < b["min"]:
            bad.append("%s %.3f < floor %.2f" % (row, v, b["min"]))
        elif "max" in b and v > b["max"]:
            bad.append("%s %.3f > ceiling %.2f" % (row, v, b["max"]))
    return bad


class RealLabels(unittest.TestCase):
    def test_bounds_cover_every_row(self):
        self.assertEqual(sorted(load()["bounds"]), sorted(real_labels.ROW_KEYS))

    def test_out_of_bounds_is_reported(self):
        self.assertEqual(out_of_bounds({"a": 0.5, "b": 0.5}, {"a": {"min": 0.4}, "b": {"max": 0.6}}), [])
        self.assertEqual(len(out_of_bounds({"a": 0.3, "b": 0.7}, {"a": {"min": 0.4}, "b": {"max": 0.6}})), 2)
        self.assertEqual(len(out_of_bounds({"a": None}, {"a": {"min": 0.4}})), 1)

    def test_defaults_within_bounds_on_real_annotated_frames(self):
        spec = load()
        got = measure(spec)
        if got is None:
            self.skipTest("the annotated real frames are absent (%s)" % ", ".join(spec["frames"]))
        bad = out_of_bounds(got, spec["bounds"])
        self.assertFalse(bad, "; ".join(bad))


if __name__ == "__main__":
    if "--measure" in sys.argv:
        got = measure(load())
        print("annotated real frames absent" if got is None else
              json.dumps({k: None if v is None else round(v, 3) for k, v in got.items()}))
        sys.exit(0)
    unittest.main()
