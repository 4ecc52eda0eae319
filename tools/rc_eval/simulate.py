"""Simulates one rotating-LiDAR sweep through a scene, with per-point ground truth.

Ground-truth classes (field `gt`), following issue 29's definitions:
  0 unknown    solid samples next to vegetation along the ring (whether that is a depth jump
               depends on where a leaf happened to be hit), and other ambiguous transitions
  1 planar     a planar face (ground, pavement, box faces, ramps)
  2 crease     the two samples on either side of a fold between two faces, when the surface is
               continuous across the fold and the faces meet at >= crease_min_angle_deg
  3 depth jump the near (occluding) sample of a range discontinuity along the ring; the far
               sample is the shadow of the occluder and keeps the class of its own surface
               (planar, curved, ...), so a Corner there is a false positive (LOAM drops it too)
  4 vegetation a return from inside a vegetation volume (crown, bush, hedge)
  5 curved     smooth curved surface that is not thin (car cabins, cylinders wider than
               raycast.THIN_MAX_WIDTH)
  6 thin       every sample on a thin object: poles, trunks, sign posts (cylinders at most
               THIN_MAX_WIDTH across) and sign plates; seen as narrow runs bounded by depth jumps,
               stacked over rings, they are features (Edge or Corner), not Plane. Thin takes
               precedence over crease and jump on the object itself (its silhouette samples are
               thin, not depth jump); a thin sample beside vegetation stays unknown.

Transitions are found exactly, not by thresholds on range: for two neighbouring samples on
different surfaces, the ray is swept between them (bisection on the interpolated ray) to the
point where the hit surface changes; if the hit points just before and after it coincide, the
surface is continuous there (a fold), otherwise it is a depth jump, whose near side is the
surface hit at the smaller range just either side of that point.
"""
import numpy as np

from .raycast import CURVED, PLANAR, VEGETATION, cast, rot_z

GT_UNKNOWN, GT_PLANAR, GT_CREASE, GT_JUMP, GT_VEGETATION, GT_CURVED, GT_THIN = 0, 1, 2, 3, 4, 5, 6
GT_NAMES = {0: "unknown", 1: "planar", 2: "crease", 3: "depth_jump", 4: "vegetation", 5: "curved",
            6: "thin"}
BISECTION_STEPS = 24


def _rays(sensor, az_deg, elev_deg, t_abs, velocity, yaw_rate):
    """World-frame origins and directions of rays, and their sensor-frame directions."""
    az, el = np.radians(az_deg), np.radians(elev_deg)
    ds = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)
    yaw = yaw_rate * t_abs
    c, s = np.cos(yaw), np.sin(yaw)
    dw = np.stack([c * ds[..., 0] - s * ds[..., 1], s * ds[..., 0] + c * ds[..., 1], ds[..., 2]], axis=-1)
    o = np.asarray(velocity, float) * t_abs[..., None]
    return o, dw, ds


def simulate_frame(sensor, shapes, frame_index, noise_sigma, dropout, velocity, yaw_rate,
                   crease_min_angle_deg, rng):
    """Returns a dict of (rays x columns) arrays: xyz (sensor frame at firing time), ring, time,
    intensity, gt and valid; rows are lasers in firing order, columns are firing blocks."""
    n_b, n_c = sensor.n_beams, sensor.n_columns
    col = np.arange(n_c)
    t_rel = col[None, :] * sensor.block_period + np.arange(n_b)[:, None] * sensor.firing_dt
    t_abs = frame_index * 60.0 / sensor.rpm + t_rel
    rate = 360.0 * sensor.rpm / 60.0  # deg/s, clockwise
    az = 180.0 - rate * t_rel
    elev = np.broadcast_to(sensor.elevation_deg[:, None], (n_b, n_c))
    o, dw, ds = _rays(sensor, az, elev, t_abs, velocity, yaw_rate)
    t, shp, face, _, kind = cast(shapes, o.reshape(-1, 3), dw.reshape(-1, 3))
    t, shp, face, kind = (a.reshape(n_b, n_c) for a in (t, shp, face, kind))
    valid = np.isfinite(t) & (t >= sensor.min_range) & (t <= sensor.max_range)
    gt = np.where(valid, kind, GT_UNKNOWN).astype(np.uint8)

    # neighbouring samples along each ring: column c and c+1 of the same laser (circular)
    a_idx = np.arange(n_c)
    b_idx = (a_idx + 1) % n_c
    va, vb = valid[:, a_idx], valid[:, b_idx]
    solid_a, solid_b = kind[:, a_idx] != VEGETATION, kind[:, b_idx] != VEGETATION
    veg_adjacent = np.zeros_like(valid)
    mixed = va & vb & (solid_a != solid_b)
    rows, cols = np.nonzero(mixed)
    for r, c in zip(rows, cols):  # the solid side of a vegetation boundary is ambiguous
        cc = c if solid_a[r, c] else b_idx[c]
        veg_adjacent[r, cc] = True
    gt[veg_adjacent] = GT_UNKNOWN

    change = va & vb & solid_a & solid_b & ((shp[:, a_idx] != shp[:, b_idx]) | (face[:, a_idx] != face[:, b_idx]))
    rows, cols = np.nonzero(change)
    cols_b = b_idx[cols]
    crease, jump, unknown, near_a = _classify_transitions(
        shapes, sensor, rows, cols, cols_b, az, elev, t_abs, velocity, yaw_rate,
        (shp[rows, cols], face[rows, cols]), (shp[rows, cols_b], face[rows, cols_b]),
        crease_min_angle_deg, n_c)
    for mask, cls in ((unknown, GT_UNKNOWN), (crease, GT_CREASE)):
        gt[rows[mask], cols[mask]] = cls
        gt[rows[mask], cols_b[mask]] = cls
    # a depth jump marks its near side only; the far side keeps its surface's class
    gt[rows[jump], np.where(near_a[jump], cols[jump], cols_b[jump])] = GT_JUMP
    thin_shape = np.array([bool(getattr(s, "thin", False)) for s in shapes] + [False])
    thin = valid & thin_shape[shp]  # shp == -1 (no hit) reads the trailing False
    gt[thin & (gt != GT_UNKNOWN)] = GT_THIN

    rng_meas = t + rng.normal(0.0, noise_sigma, t.shape) if noise_sigma > 0 else t.copy()
    valid &= rng.random(t.shape) >= dropout
    gt[~valid] = GT_UNKNOWN
    xyz = ds * np.where(valid, rng_meas, np.nan)[..., None]
    base_int = np.select([kind == PLANAR, kind == CURVED, kind == VEGETATION], [40.0, 70.0, 15.0], 0.0)
    intensity = np.clip(base_int + rng.normal(0, 3.0, t.shape), 0, 255)
    ring = np.broadcast_to(sensor.ring[:, None], (n_b, n_c))
    return {"xyz": xyz, "ring": ring, "time": t_rel, "intensity": intensity, "gt": gt, "valid": valid}


def _classify_transitions(shapes, sensor, rows, ca, cb, az, elev, t_abs, velocity, yaw_rate,
                          key_a, key_b, crease_min_angle_deg, n_c):
    n = len(rows)
    if n == 0:
        z = np.zeros(0, dtype=bool)
        return z, z, z, z
    az_a, az_b = az[rows, ca], az[rows, cb]
    az_b = np.where(cb < ca, az_b - 360.0, az_b)  # across the seam the azimuth keeps turning
    t_a, t_b = t_abs[rows, ca], t_abs[rows, cb]
    t_b = np.where(cb < ca, t_a + (t_abs[rows, 1] - t_abs[rows, 0]), t_b)
    el = elev[rows, ca]

    def probe(s):
        o, d, _ = _rays(sensor, az_a + s * (az_b - az_a), el, t_a + s * (t_b - t_a), velocity, yaw_rate)
        tt, sh, fc, nn, _ = cast(shapes, o, d, solid_only=True)
        return o + np.where(np.isfinite(tt), tt, np.nan)[:, None] * d, sh, fc, nn, tt

    lo, hi = np.zeros(n), np.ones(n)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        _, sh, fc, _, _ = probe(mid)
        same = (sh == key_a[0]) & (fc == key_a[1])
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    p_lo, _, _, n_lo, t_lo = probe(lo)
    p_hi, sh_hi, fc_hi, n_hi, t_hi = probe(hi)
    gap = np.linalg.norm(p_lo - p_hi, axis=1)
    continuous = np.isfinite(gap) & (gap < 1e-3 + 1e-4 * np.nan_to_num(t_lo, posinf=0.0))
    direct = (sh_hi == key_b[0]) & (fc_hi == key_b[1])
    fold = np.degrees(np.arccos(np.clip(np.sum(n_lo * n_hi, axis=1), -1, 1)))
    crease = continuous & direct & (fold >= crease_min_angle_deg)
    jump = ~continuous
    unknown = continuous & ~direct
    near_a = ~(np.nan_to_num(t_hi, nan=np.inf) < np.nan_to_num(t_lo, nan=np.inf))  # a's surface nearer
    return crease, jump, unknown, near_a


def to_point_arrays(sensor, frame):
    """Flattens a frame in the order the driver emits points: column by column, lasers in
    firing order; unorganized clouds drop no-returns, organized ones (rows = rings, lowest
    first) keep them as NaN."""
    if sensor.organized:
        order = np.argsort(sensor.ring)  # row r holds the laser whose ring is r
        return {k: np.ascontiguousarray(v[order]).reshape(-1) if k != "xyz" else
                np.ascontiguousarray(v[order]).reshape(-1, 3) for k, v in frame.items()}, (sensor.n_beams, sensor.n_columns)
    keep = frame["valid"].T.reshape(-1)
    out = {}
    for k, v in frame.items():
        flat = np.swapaxes(v, 0, 1).reshape((-1, 3) if k == "xyz" else (-1,))
        out[k] = flat[keep]
    return out, (1, int(keep.sum()))


def gt_counts(gt):
    return {GT_NAMES[c]: int(np.sum(gt == c)) for c in GT_NAMES}


__all__ = ["simulate_frame", "to_point_arrays", "gt_counts", "GT_NAMES", "rot_z"]
