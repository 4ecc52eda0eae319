"""Labels against simulator ground truth: per-class precision and recall.

Point-wise classes
  Plane  vs gt planar (1). Recall over planar points. Precision over Plane predictions on points
         whose truth is planar or vegetation: curved surfaces (5) are don't-care for Plane (the
         core's Plane includes gently curved smooth surfaces) and so are the fold / jump samples
         (2, 3), which lie on a face on one side; unknown (0) is always don't-care.
  Rough  vs gt vegetation (4). Precision over Rough predictions with known truth.
Run-wise classes, per ring with one-sample tolerance
  Edge   vs gt crease runs (2);  Corner vs gt depth-jump runs (3);  Feature = Edge or Corner vs
         crease or jump (localisation without the type).
  A gt run is found when a predicted point of the class lies within one sample of it. A
  predicted run (neighbouring points of the class along a ring) is a true positive when it lies
  within one sample of a gt run, ignored when it lies within one sample of an unknown (0) point
  only, else a false positive (so Edge/Corner on curved surfaces, planes or vegetation count).
Samples are placed on a per-ring azimuth column grid measured from the data, so a no-return
leaves a hole rather than joining its neighbours.
"""
import numpy as np

RUN_CLASSES = {"Edge": ((2,), (2,)), "Corner": ((3,), (3,)), "Feature": ((2, 3), (2, 3))}


def ring_columns(x, y, ring):
    """Integer azimuth column of each point within its ring, and the number of columns."""
    az = np.arctan2(y, x)
    order = np.lexsort((az, ring))
    d = np.diff(az[order])
    same = np.diff(ring[order]) == 0
    d = d[same & (d > 1e-7)]
    step = float(np.median(d)) if len(d) else 2 * np.pi
    n_cols = max(int(round(2 * np.pi / step)), 1)
    col = np.zeros(len(x), dtype=np.int64)
    for r in np.unique(ring):
        m = ring == r
        u = az[m] / step
        off = np.angle(np.mean(np.exp(2j * np.pi * u))) / (2 * np.pi)  # ring's firing offset
        col[m] = np.mod(np.round(u - off).astype(np.int64), n_cols)
    return col, n_cols


def _runs(mask):
    """Runs of True in a circular boolean array: list of index arrays."""
    n = len(mask)
    if not mask.any():
        return []
    if mask.all():
        return [np.arange(n)]
    start = int(np.argmin(mask))  # a False: runs cannot wrap past it
    m = np.roll(mask, -start)
    d = np.diff(np.concatenate(([0], m.astype(np.int8), [0])))
    s, e = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
    return [(np.arange(a, b) + start) % n for a, b in zip(s, e)]


def _dilate(mask):
    return mask | np.roll(mask, 1) | np.roll(mask, -1)


def _counts():
    # predicted units (points or runs) right / wrong; truth units (points or runs) found / missed
    return {"pred_tp": 0, "pred_fp": 0, "gt_tp": 0, "gt_fn": 0}


def score(label, gt, ring, x, y):
    """Counts per class for one frame (finite points only)."""
    ok = np.isfinite(x) & np.isfinite(y)
    label, gt, ring, x, y = label[ok], gt[ok], ring[ok].astype(np.int64), x[ok], y[ok]
    c = {k: _counts() for k in ("Plane", "Rough", *RUN_CLASSES)}
    p1, g1 = label == 1, gt == 1
    c["Plane"]["pred_tp"] = c["Plane"]["gt_tp"] = int(np.sum(p1 & g1))
    c["Plane"]["pred_fp"] = int(np.sum(p1 & (gt == 4)))
    c["Plane"]["gt_fn"] = int(np.sum(~p1 & g1))
    p4, g4 = label == 4, gt == 4
    c["Rough"]["pred_tp"] = c["Rough"]["gt_tp"] = int(np.sum(p4 & g4))
    c["Rough"]["pred_fp"] = int(np.sum(p4 & ~g4 & (gt != 0)))
    c["Rough"]["gt_fn"] = int(np.sum(~p4 & g4))
    if len(x) == 0:
        return c
    col, n_cols = ring_columns(x, y, ring)
    for r in np.unique(ring):
        m = ring == r
        cols = col[m]
        for name, (pred_labels, gt_classes) in RUN_CLASSES.items():
            pred = np.zeros(n_cols, bool)
            truth = np.zeros(n_cols, bool)
            unknown = np.zeros(n_cols, bool)
            pred[cols[np.isin(label[m], pred_labels)]] = True
            truth[cols[np.isin(gt[m], gt_classes)]] = True
            unknown[cols[gt[m] == 0]] = True
            near_pred, near_truth, near_unknown = _dilate(pred), _dilate(truth), _dilate(unknown)
            for run in _runs(truth):
                c[name]["gt_tp" if near_pred[run].any() else "gt_fn"] += 1
            for run in _runs(pred):
                if near_truth[run].any():
                    c[name]["pred_tp"] += 1
                elif not near_unknown[run].any():
                    c[name]["pred_fp"] += 1
    return c


def add(total, c):
    for k, v in c.items():
        t = total.setdefault(k, _counts())
        for kk in v:
            t[kk] += v[kk]
    return total


def rates(c):
    """precision, recall from counts (None when undefined)."""
    n_pred, n_gt = c["pred_tp"] + c["pred_fp"], c["gt_tp"] + c["gt_fn"]
    return (c["pred_tp"] / n_pred if n_pred else None, c["gt_tp"] / n_gt if n_gt else None)
