"""Ground-truth accuracy of one labelling method over simulated bags."""
import os

import numpy as np

from .runner import labelled_frames, run_method
from .scoring import add, rates, score

CLASSES = ("Plane", "Edge", "Corner", "Rough", "Feature", "Thin")


def score_bag(labelled_bag):
    total = {}
    frames = labelled_frames(labelled_bag)
    if not frames:
        raise RuntimeError("%s has no labelled clouds" % labelled_bag)
    for a in frames:
        if "gt" not in a.dtype.names or "label" not in a.dtype.names:
            raise RuntimeError("%s: labelled cloud lacks 'gt' or 'label'" % labelled_bag)
        add(total, score(a["label"], a["gt"], a["ring"], a["x"].astype(float), a["y"].astype(float)))
    return total


def evaluate_method(method, bags, work_dir, params=None, tag="run"):
    """Counts summed over bags, and the tool's wall time per bag."""
    total, times = {}, []
    for i, bag in enumerate(bags):
        out = os.path.join(work_dir, "%s_%d.bag" % (tag, i))
        times.append(run_method(method, bag, out, params))
        add(total, score_bag(out))
        os.unlink(out)
    return total, times


def summary(counts):
    """{class: (precision, recall)}"""
    return {k: rates(counts[k]) for k in CLASSES if k in counts}


def f1(p, r):
    if p is None or r is None or p + r == 0:
        return 0.0
    return 2 * p * r / (p + r)


def mean_f1(counts):
    s = summary(counts)
    return float(np.mean([f1(*s[k]) for k in ("Plane", "Edge", "Corner", "Rough")]))
