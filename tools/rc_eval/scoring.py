"""Labels against simulator ground truth: per-class precision and recall.

Labels: 1 Plane, 2 Edge, 3 Corner, 4 Rough. Ground truth (tools/rc_eval/simulate.py): 0 unknown,
1 planar, 2 crease, 3 depth jump (near side only), 4 vegetation, 5 curved, 6 thin object.

Point-wise classes
  Plane  vs gt planar (1). Recall over planar points (the far, shadow side of a depth jump is
         planar too). Precision over Plane predictions on points whose truth is planar,
         vegetation or thin (4, 6: Plane there is wrong): curved surfaces (5) are don't-care for
         Plane (the core's Plane includes gently curved smooth surfaces) and so are the fold /
         jump samples (2, 3), which lie on a face on one side; unknown (0) is always don't-care.
  Rough  vs gt vegetation (4). Precision over Rough predictions with known truth.
Run-wise classes, per ring with one-sample tolerance
  Edge    vs gt crease runs (2) and thin-object runs (6). A crease run is found by an Edge label,
          a thin run by an Edge or a Corner label (issue 29: a pole, trunk or sign is Edge/Corner).
          Predicted Edge runs are right near a crease or a thin run.
  Corner  vs gt depth-jump runs (3), found by a Corner label. Predicted Corner runs are right near
          a jump run or on / beside a thin object (its silhouette is a jump too); thin runs are
          not in Corner's recall (they are Edge's).
  Feature Edge or Corner vs crease, jump or thin runs (localisation without the type).
  Thin    recall only: thin runs found by an Edge or Corner label (precision undefined, "-").
  A gt run is found when a predicted point of a label that finds it lies within one sample of
  it. A predicted run (neighbouring points of the class along a ring) is a true positive when it
  lies within one sample of a gt run it may stand for, ignored when it lies within one sample of
  an unknown (0) point only, else a false positive (so Edge/Corner on curved surfaces, planes,
  vegetation or the shadow side of a jump count).
  The tolerance never reaches across a depth jump onto its far side: a shadow sample (planar or
  curved truth, beside a jump or thin sample that is nearer by more than SHADOW_MARGIN_M +
  SHADOW_MARGIN_REL x its range, horizontally) neither counts as "within one sample" of the jump
  for a predicted run nor finds the jump with its own label. A Corner on the far side only is
  thus a false positive, as issue 29's occlusion-aware jumps define it. The margin (5 cm + 2 %)
  is the depth step that no planar face seen at less than ~80 deg incidence makes between
  neighbouring samples, and it is well above the simulated range noise (<= 3 cm).
Samples are placed on a per-ring azimuth column grid measured from the data, so a no-return
leaves a hole rather than joining its neighbours.
"""
import numpy as np

# name: (labels predicted, [(gt classes forming runs, labels that find them)], gt classes a
# prediction may also sit on). Thin has no predicted side (recall only).
RUN_CLASSES = {
    "Edge": ((2,), [((2,), (2,)), ((6,), (2, 3))], ()),
    "Corner": ((3,), [((3,), (3,))], (6,)),
    "Feature": ((2, 3), [((2, 3, 6), (2, 3))], ()),
    "Thin": (None, [((6,), (2, 3))], ()),
}
SHADOW_MARGIN_M, SHADOW_MARGIN_REL = 0.05, 0.02


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
    c["Plane"]["pred_fp"] = int(np.sum(p1 & np.isin(gt, (4, 6))))
    c["Plane"]["gt_fn"] = int(np.sum(~p1 & g1))
    p4, g4 = label == 4, gt == 4
    c["Rough"]["pred_tp"] = c["Rough"]["gt_tp"] = int(np.sum(p4 & g4))
    c["Rough"]["pred_fp"] = int(np.sum(p4 & ~g4 & (gt != 0)))
    c["Rough"]["gt_fn"] = int(np.sum(~p4 & g4))
    if len(x) == 0:
        return c
    col, n_cols = ring_columns(x, y, ring)
    rng_h = np.hypot(x, y)
    for r in np.unique(ring):
        m = ring == r
        cols, gr, lr = col[m], gt[m], label[m]

        def where(values, classes):  # columns holding a point whose value is in classes
            out = np.zeros(n_cols, bool)
            out[cols[np.isin(values, classes)]] = True
            return out

        g = np.full(n_cols, -1, np.int64)
        rh = np.full(n_cols, np.nan)
        g[cols], rh[cols] = gr, rng_h[m]
        shadow = _shadow(g, rh)
        near_unknown = _dilate(where(gr, (0,)))
        for name, (pred_labels, truth, also_right) in RUN_CLASSES.items():
            for classes, finders in truth:
                near_pred = _dilate(where(lr, finders) & ~shadow)
                for run in _runs(where(gr, classes)):
                    c[name]["gt_tp" if near_pred[run].any() else "gt_fn"] += 1
            if pred_labels is None:
                continue
            right = [k for classes, _ in truth for k in classes] + list(also_right)
            near_truth = _dilate(where(gr, right)) & ~shadow
            for run in _runs(where(lr, pred_labels)):
                if near_truth[run].any():
                    c[name]["pred_tp"] += 1
                elif not near_unknown[run].any():
                    c[name]["pred_fp"] += 1
    return c


def _shadow(g, rh):
    """Far-side samples of depth jumps along one ring (columns; g = gt, -1 where no point)."""
    out = np.zeros(len(g), bool)
    surface = np.isin(g, (1, 5))
    for step in (1, -1):
        g_n, r_n = np.roll(g, step), np.roll(rh, step)
        with np.errstate(invalid="ignore"):
            farther = rh - r_n > SHADOW_MARGIN_M + SHADOW_MARGIN_REL * r_n
        out |= surface & np.isin(g_n, (3, 6)) & farther
    return out


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
