"""How far local geometric cues can take the Plane/Rough split on real annotated scans (issue 29's
two purity rows), beyond the defaults' labels.

For every point the defaults label Plane or Rough, a set of cues is computed from the labelled
cloud alone (its ring field and coordinates give the scan grid: ring neighbours by azimuth, the
nearest sample on the ring above and below). Printed:
  1. each cue's separation of vegetation from building among the points the defaults call Plane
     (what Plane purity needs) and among those they call Rough (what Rough purity needs), as the
     AUC (0.5: no signal; 1 or 0: perfect);
  2. a bound: a logistic regression over all cues at once, trained on the other frames and applied
     to each frame in turn, relabels the Plane and Rough points; the issue's rows for several
     probability thresholds. If no threshold meets both purities at building -> Plane >= 0.90,
     a hand rule on these cues will not either (the frames are consecutive, so the bound is, if
     anything, optimistic);
  3. the same with gradient-boosted trees, which can find any rule that cuts the cues into boxes
     (range or height included, they can also learn where this one street's objects are: leave
     such cues out with --without 'height z' --without 'range (log)'), and each cue's share of
     the trees' split gain. With --sides, each side of the street is scored by models of the
     other side only, so that a model cannot have learnt the very objects it scores. With
     --two-frames, three more cues from the frames before and after (ground-truth poses): what a
     second look at the same surface adds.

  tools/label_cues [--data DIR] [--without CUE ...] [--sides] [--two-frames]
"""
import argparse
import os
import tempfile

import numpy as np

from . import real_labels as rl
from .runner import labelled_frames, run_method

WINDOW = 4  # samples each way along the ring; plus the same on the rings above and below
POSITIVE = (70, 71)  # vegetation, trunk: should be Rough
NEGATIVE = rl.GROUND + rl.BUILDING  # should be Plane


def grid_links(a):
    """(prev, next, up, down) indices per point, -1 for none: neighbours along the ring in azimuth
    order, and the nearest azimuth on the ring numbered one higher / lower (within 0.01 rad)."""
    n = len(a)
    ring = a["ring"].astype(np.int64)
    ok = np.isfinite(a["x"]) & np.isfinite(a["y"]) & np.isfinite(a["z"])
    az = np.arctan2(a["y"].astype(np.float64), a["x"].astype(np.float64))
    links = [-np.ones(n, np.int64) for _ in range(4)]
    rings = {}
    for r in np.unique(ring[ok]):
        idx = np.flatnonzero(ok & (ring == r))
        idx = idx[np.argsort(az[idx], kind="stable")]
        rings[r] = (idx, az[idx])
        links[0][idx[1:]], links[1][idx[:-1]] = idx[:-1], idx[1:]
    for r, (idx, a_r) in rings.items():
        for step, out in ((1, links[2]), (-1, links[3])):
            if r + step not in rings:
                continue
            j, a_j = rings[r + step]
            k = np.searchsorted(a_j, a_r)
            lo, hi = np.clip(k - 1, 0, len(a_j) - 1), np.clip(k, 0, len(a_j) - 1)
            pick = np.where(np.abs(a_j[lo] - a_r) < np.abs(a_j[hi] - a_r), lo, hi)
            near = np.abs(a_j[pick] - a_r) < 0.01
            out[idx[near]] = j[pick[near]]
    return links


def window(links):
    """(n, 27) indices: WINDOW samples each way along the ring, on the point's ring and the rings
    above and below (a missing neighbour repeats the last one found)."""
    prev, nxt, up, down = links
    n = len(prev)
    here = np.arange(n)
    cols = [here]
    for nb in (prev, nxt):
        cur = here
        for _ in range(WINDOW):
            cur = np.where(nb[cur] >= 0, nb[cur], cur)
            cols.append(cur)
    rows = list(cols)
    for nb in (up, down):
        rows += [np.where(nb[c] >= 0, nb[c], c) for c in cols]
    return np.stack(rows, axis=1)


def cues(a):
    """{name: per-point value} from one labelled cloud."""
    links = grid_links(a)
    prev, nxt, up, down = links
    n = len(a)
    here = np.arange(n)
    xyz = np.stack([a["x"], a["y"], a["z"]], axis=1).astype(np.float64)
    rho = np.linalg.norm(xyz, axis=1)

    def second_difference(p, q):
        p, q = np.where(p >= 0, p, here), np.where(q >= 0, q, here)
        return np.abs(rho[p] + rho[q] - 2 * rho) / rho

    W = window(links)
    along, across = second_difference(prev, nxt)[W], second_difference(up, down)[W]
    log = lambda v: np.log(np.maximum(v, 1e-12))  # noqa: E731
    steep = np.zeros(n, bool)
    for nb in (up, down):
        d = xyz[np.where(nb >= 0, nb, here)] - xyz
        steep |= (nb >= 0) & (np.abs(d[:, 2]) > np.hypot(d[:, 0], d[:, 1]))
    return {
        "smoothness S (log)": log(a["smoothness"]),
        "|curvature| (log)": log(np.abs(a["curvature"])),
        "along-ring 2nd difference / range, window median (log)": log(np.median(along, 1)),
        "along-ring 2nd difference / range, window mean (log)": log(along.mean(1)),
        "along-ring: window lower quartile / mean": np.percentile(along, 25, 1) / (along.mean(1) + 1e-12),
        "cross-ring 2nd difference / range (log)": log(across[:, 0]),
        "cross-ring 2nd difference / range, window median (log)": log(np.median(across, 1)),
        "steep (ring above or below mostly vertical)": steep.astype(float),
        "height z": xyz[:, 2],
        "range (log)": log(rho),
        "Rough share of the window (the defaults' labels)": (a["label"] == rl.ROUGH)[W].mean(1),
    }


def sequence_cues(xyz, k, sequence):
    """Cues from the frames before and after frame k of a sequence with ground-truth poses
    (sequence: (clouds, poses)), moved into frame k: the other frame samples the same surface at
    other places, so a wall stays thin and foliage does not. The least over the frames there are."""
    from scipy.spatial import cKDTree
    clouds, poses = sequence
    rho = np.linalg.norm(xyz, axis=1)
    nearest, residual, variation = [], [], []
    for j in (k - 1, k + 1):
        if not 0 <= j < len(clouds):
            continue
        T = np.linalg.inv(poses[k]) @ poses[j]
        moved = clouds[j] @ T[:3, :3].T + T[:3, 3]
        distance, idx = cKDTree(moved).query(xyz, k=10)
        nb = moved[idx]
        centre = nb.mean(1)
        w, v = np.linalg.eigh(np.einsum("nki,nkj->nij", nb - centre[:, None], nb - centre[:, None]))
        nearest.append(distance[:, 0] / rho)
        residual.append(np.abs(np.einsum("ni,ni->n", xyz - centre, v[:, :, 0])) / rho)
        variation.append(w[:, 0] / np.maximum(w.sum(1), 1e-300))
    log = lambda v: np.log(np.maximum(np.min(v, 0), 1e-12))  # noqa: E731
    return {
        "other frame: distance to the nearest point / rho (log)": log(nearest),
        "other frame: distance to the neighbours' plane / rho (log)": log(residual),
        "other frame: surface variation of the neighbours": np.min(variation, 0),
    }


def load_sequence(data_dir):
    """The clouds and poses of the KITTI sequence beside the labelled frames (its frames 0-15
    hold frames 0-2 of the labelled ones), or None."""
    base = os.path.join(os.path.dirname(os.path.abspath(data_dir)), "sequences", "kitti_seq00_16frames")
    if not (os.path.isfile(base + ".bag") and os.path.isfile(base + "_poses.npy")):
        return None
    from .cloud_io import read_bag_clouds
    clouds = [np.stack([c["x"], c["y"], c["z"]], 1).astype(np.float64)
              for _, c, _ in read_bag_clouds(base + ".bag", rl.TOPIC)]
    return clouds, np.load(base + "_poses.npy")


def auc(pos, neg):
    """P(a positive's value > a negative's), ties half: the Mann-Whitney U over the product (over
    the finite values: a point without a curvature, say, is no evidence either way)."""
    from scipy.stats import mannwhitneyu
    pos, neg = pos[np.isfinite(pos)], neg[np.isfinite(neg)]
    if len(pos) == 0 or len(neg) == 0:
        return float("nan")
    return float(mannwhitneyu(pos, neg).statistic) / (len(pos) * len(neg))


def fit_logistic(X, y, iterations=600, rate=0.5, l2=1e-3):
    """A logistic regression by gradient descent on standardized features; returns p(X)."""
    mu, sd = X.mean(0), X.std(0) + 1e-9
    Z = (X - mu) / sd
    w, b = np.zeros(X.shape[1]), 0.0
    for _ in range(iterations):
        p = 1.0 / (1.0 + np.exp(-(Z @ w + b)))
        w -= rate * (Z.T @ (p - y) / len(y) + l2 * w)
        b -= rate * float(np.mean(p - y))
    return lambda Q: 1.0 / (1.0 + np.exp(-(((Q - mu) / sd) @ w + b)))


def fit_boosted(X, y, rounds=200, depth=3, rate=0.2, bins=32, l2=1.0, min_hessian=20.0):
    """Gradient-boosted trees (logistic loss, Newton leaves, splits on quantile bins of each cue):
    the non-linear counterpart of fit_logistic, able to find any rule that cuts the cues into
    boxes. Returns p(X)."""
    edges = [np.unique(np.quantile(X[:, j], np.linspace(0, 1, bins + 1)[1:-1])) for j in range(X.shape[1])]

    def binned(Q):
        return np.stack([np.searchsorted(e, Q[:, j], side="right") for j, e in enumerate(edges)], 1).astype(np.int32)

    B = binned(X)
    score = np.zeros(len(y))
    trees = []
    gains = np.zeros(X.shape[1])

    def grow(idx, g, h, level):
        G, H = g[idx].sum(), h[idx].sum()
        if level == depth or H < 2 * min_hessian:
            return -rate * G / (H + l2)
        best = None
        for j in range(B.shape[1]):
            gl = np.cumsum(np.bincount(B[idx, j], weights=g[idx], minlength=bins + 1))[:-1]
            hl = np.cumsum(np.bincount(B[idx, j], weights=h[idx], minlength=bins + 1))[:-1]
            ok = (hl >= min_hessian) & (H - hl >= min_hessian)
            gain = np.where(ok, gl ** 2 / (hl + l2) + (G - gl) ** 2 / (H - hl + l2), -np.inf)
            t = int(np.argmax(gain))
            if np.isfinite(gain[t]) and (best is None or gain[t] > best[0]):
                best = (gain[t], j, t)
        if best is None:
            return -rate * G / (H + l2)
        gain, j, t = best
        gains[j] += gain - G ** 2 / (H + l2)
        left = B[idx, j] <= t
        return (j, t, grow(idx[left], g, h, level + 1), grow(idx[~left], g, h, level + 1))

    def apply(tree, Bq, idx, out):
        if not isinstance(tree, tuple):
            out[idx] += tree
            return
        j, t, lo, hi = tree
        left = Bq[idx, j] <= t
        apply(lo, Bq, idx[left], out)
        apply(hi, Bq, idx[~left], out)

    everything = np.arange(len(y))
    for _ in range(rounds):
        p = 1.0 / (1.0 + np.exp(-score))
        tree = grow(everything, p - y, p * (1.0 - p), 0)
        trees.append(tree)
        apply(tree, B, everything, score)

    def predict(Q):
        Bq, out = binned(Q), np.zeros(len(Q))
        for tree in trees:
            apply(tree, Bq, np.arange(len(Q)), out)
        return 1.0 / (1.0 + np.exp(-out))
    predict.gain_share = gains / max(gains.sum(), 1e-300)
    return predict


def main(argv):
    p = argparse.ArgumentParser(prog="label_cues", description=__doc__.split("\n\n")[0])
    p.add_argument("--data", help="labelled bags (default as evaluate_real)")
    p.add_argument("--without", action="append", default=[], metavar="CUE",
                   help="leave out the cue of this name (repeatable), e.g. 'height z'")
    p.add_argument("--sides", action="store_true",
                   help="score each side of the street (y > 0, y <= 0) by models of the other side: "
                        "no object is in both training and scoring")
    p.add_argument("--two-frames", action="store_true",
                   help="add cues from the frames before and after, moved by the ground-truth poses "
                        "(the KITTI sequence beside the labelled frames)")
    args = p.parse_args(argv)
    bags = rl.labelled_bags(args.data or rl.default_data_dir())
    if len(bags) < 2:
        print("label_cues: skipping: needs at least two labelled bags (the shared KITTI frames)")
        return 0
    sequence = load_sequence(args.data or rl.default_data_dir()) if args.two_frames else None
    if args.two_frames and sequence is None:
        print("label_cues: --two-frames needs ../sequences/kitti_seq00_16frames.bag and _poses.npy beside the data")
        return 1
    frames = []
    with tempfile.TemporaryDirectory() as work:
        for b in bags:
            out = os.path.join(work, "labelled.bag")
            run_method("ours", b, out, {}, rl.TOPIC)
            for (name, xyz, sem), a in zip(rl.load_frames(b, rl.TOPIC), labelled_frames(out)):
                c = cues(a)
                if sequence:  # (the labelled frame's number in sequence 00 ends its name)
                    xyz_a = np.stack([a["x"], a["y"], a["z"]], 1).astype(np.float64)
                    c.update(sequence_cues(xyz_a, int(name.rsplit("_", 1)[1]), sequence))
                frames.append((name, sem, a, rl.thin_clusters(xyz, sem), c))
    unknown = [w for w in args.without if w not in frames[0][4]]
    if unknown:
        print("label_cues: no cue named %s; the cues: %s" % (", ".join(map(repr, unknown)),
                                                             ", ".join(map(repr, frames[0][4]))))
        return 2
    names = [c for c in frames[0][4] if c not in args.without]
    print("| cue | AUC veg > building, among Plane | AUC veg > ground+building, among Rough |")
    print("|---|---|---|")
    for c in names:
        cell = []
        for label, neg in ((rl.PLANE, rl.BUILDING), (rl.ROUGH, NEGATIVE)):
            pos = np.concatenate([f[4][c][(f[2]["label"] == label) & (f[1] == 70)] for f in frames])
            bad = np.concatenate([f[4][c][(f[2]["label"] == label) & np.isin(f[1], neg)] for f in frames])
            cell.append("%.3f" % auc(pos, bad))
        print("| %s | %s |" % (c, " | ".join(cell)))
    X = [np.nan_to_num(np.stack([f[4][c] for c in names], 1), posinf=0.0, neginf=0.0) for f in frames]
    for title, fit in (("logistic regression", fit_logistic), ("gradient-boosted trees", fit_boosted)):
        bound(frames, names, X, title, fit, args.sides)
    return 0


def bound(frames, names, X, title, fit, sides):
    """The issue's rows with the Plane and Rough points relabelled by a model of the cues, each
    frame scored by a model trained on the others (with `sides`, on their other side of the
    street: other objects), for several probability thresholds."""
    probability, shares = [], []
    for k in range(len(frames)):
        rest = [j for j in range(len(frames)) if j != k]
        sem = np.concatenate([frames[j][1] for j in rest])
        lab = np.concatenate([frames[j][2]["label"] for j in rest])
        left = np.concatenate([frames[j][2]["y"] > 0 for j in rest])
        train = np.isin(sem, POSITIVE + NEGATIVE) & np.isin(lab, (rl.PLANE, rl.ROUGH))
        Xr = np.concatenate([X[j] for j in rest])
        prob = np.zeros(len(X[k]))
        # with sides: the left of the street scored by a model of its right, and the reverse
        for side in ((True, False) if sides else (None,)):
            use = train if side is None else train & (left != side)
            model = fit(Xr[use], np.isin(sem[use], POSITIVE).astype(float))
            here = np.ones(len(X[k]), bool) if side is None else (frames[k][2]["y"] > 0) == side
            prob[here] = model(X[k][here])
            shares.append(getattr(model, "gain_share", None))
        probability.append(prob)
    rows = ["ground_plane", "building_plane", "vegetation_rough", "plane_purity", "rough_purity"]
    print("\nAll cues at once (%s, each frame scored by a model of the others%s):\n"
          % (title, ", side by side" if sides else ""))
    print("| threshold | " + " | ".join(rows) + " |")
    print("|---" * (len(rows) + 1) + "|")
    defaults = rl.pool([rl.frame_counts(f[2]["label"], f[1], f[3]) for f in frames])
    print("| defaults | " + " | ".join("%.3f" % rl.ratio(defaults[r]) for r in rows) + " |")
    for t in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8):
        counts = []
        for f, prob in zip(frames, probability):
            label = f[2]["label"].copy()
            split = np.isin(label, (rl.PLANE, rl.ROUGH))
            label[split] = np.where(prob[split] > t, rl.ROUGH, rl.PLANE)
            counts.append(rl.frame_counts(label, f[1], f[3]))
        c = rl.pool(counts)
        print("| %.1f | " % t + " | ".join("%.3f" % rl.ratio(c[r]) for r in rows) + " |")
    if shares[0] is not None:
        print("\nShare of the trees' split gain per cue (mean over the models):\n")
        for name, share in sorted(zip(names, np.mean(shares, 0)), key=lambda x: -x[1]):
            print("  %.3f  %s" % (share, name))
