"""Trajectory error against ground truth, for tools/slam_benchmark: TUM files, and the ATE after
aligning the first pose or the best-fitting rigid transform (Horn / Umeyama)."""


def read_tum(path):
    import numpy as np
    rows = [list(map(float, line.split())) for line in open(path) if line.strip() and not line.startswith("#")]
    return np.array(rows)

def quat_to_R(q):
    import numpy as np
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rigid_fit(src, dst):
    """The rotation R and translation t minimising sum |dst - (R src + t)|^2 (Horn / Umeyama,
    no scale): the alignment of TUM's evaluate_ate and of the evo tool's APE."""
    import numpy as np
    ms, md = src.mean(axis=0), dst.mean(axis=0)
    u, _, vt = np.linalg.svd((dst - md).T @ (src - ms))
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])  # a rotation, not a reflection
    R = u @ d @ vt
    return R, md - R @ ms


def gt_at(gt, stamps):
    """The ground truth (n >= 2, 8) TUM rows at `stamps`, interpolated between its own rows (and
    past the last, by its last step): linear in position, normalized linear in the quaternion
    (frames 0.1 s apart turn by a few degrees at most). A stamp of its own gives its row; an
    estimate stamped with the sweep's middle gets the pose there."""
    import numpy as np
    t = gt[:, 0]
    q = gt[:, 4:8].copy()
    for i in range(1, len(q)):  # one hemisphere, so that neighbours interpolate the short way
        if np.dot(q[i], q[i - 1]) < 0:
            q[i] = -q[i]
    out = np.empty((len(stamps), 8))
    for k, s in enumerate(stamps):
        j = int(np.clip(np.searchsorted(t, s, side="right") - 1, 0, len(t) - 2))
        f = (s - t[j]) / (t[j + 1] - t[j])
        out[k, 0] = s
        out[k, 1:4] = gt[j, 1:4] + f * (gt[j + 1, 1:4] - gt[j, 1:4])
        qk = q[j] + f * (q[j + 1] - q[j])
        out[k, 4:8] = qk / np.linalg.norm(qk)
    return out


def trajectory_errors(gt, est):
    """gt: (n, 8) TUM rows; est: {stamp: (t(3), q(4))}. Two ATEs, position RMSE over the frames
    that have an estimate: `ate` with the estimate aligned by the rigid transform that maps its
    first pose onto the first ground-truth pose (what a robot starting at a known pose sees), and
    `ate_aligned` with the rigid transform that best fits the whole trajectory (the usual
    benchmark definition: TUM's evaluate_ate, KITTI odometry tools, evo's APE). Drift = position
    error of the last frame / ground-truth path length (%), first-pose aligned.
    Returns (ate, drift, n, ate_aligned)."""
    import numpy as np
    none = float("nan"), float("nan"), 0, float("nan")
    if len(gt) < 2:
        return none
    last_step = gt[-1, 0] - gt[-2, 0]
    keys = [s for s in sorted(est) if gt[0, 0] - 1e-3 <= s <= gt[-1, 0] + last_step + 1e-3]
    if not keys:
        return none
    gt = gt_at(gt, keys)
    pairs = [(i, est[s]) for i, s in enumerate(keys)]
    i0, (t0, q0) = pairs[0]
    Rg0, tg0 = quat_to_R(gt[i0, 4:8]), gt[i0, 1:4]
    Re0 = quat_to_R(q0)
    Ra = Rg0 @ Re0.T
    ta = tg0 - Ra @ np.asarray(t0)
    src = np.array([np.asarray(t, dtype=float) for _, (t, _) in pairs])  # estimated positions
    dst = np.array([gt[i, 1:4] for i, _ in pairs])                        # their ground truth
    err = np.linalg.norm(dst - (src @ Ra.T + ta), axis=1)
    steps = np.linalg.norm(np.diff(gt[:, 1:4], axis=0), axis=1)
    last = pairs[-1][0]
    length = steps[i0:last].sum()
    drift = 100.0 * err[-1] / length if length > 0 else float("nan")
    if len(pairs) >= 3:
        R, t = rigid_fit(src, dst)
        ate_aligned = float(np.sqrt(np.mean(np.sum((dst - (src @ R.T + t)) ** 2, axis=1))))
    else:
        ate_aligned = float("nan")
    return float(np.sqrt(np.mean(err ** 2))), float(drift), len(pairs), ate_aligned


# ------------------------------------------------------------------ one run
