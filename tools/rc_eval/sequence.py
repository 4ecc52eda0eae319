"""Simulated LiDAR sequences with exact ground-truth poses, for the SLAM benchmark
(tools/slam_benchmark, docs/slam_benchmark.md).

The sensor moves along a planar path with turns (straights joined by circular arcs) with small
roll / pitch / height oscillations; every ray is cast from the sensor pose at its own firing
time, so the points (expressed in the sensor frame at their firing time, as a driver emits them)
carry the motion distortion of the path. The head sweeps clockwise seen from above, starting
behind the sensor (azimuth 180 deg, decreasing), as Velodynes do and as tools/rc_eval/simulate.py
models it. Ground truth: the sensor pose at each frame's stamp (its first firing), in the LiDAR
frame of frame 0, as TUM lines.

Scenes are built here from the ray caster's shapes (raycast.py), along the path: a street with
a right turn, or a courtyard walked around; deterministic from the seed. Nothing in
simulate.py / scene.py is changed or relied on beyond the shapes and cast().
"""
from dataclasses import dataclass

import numpy as np

from .raycast import Box, Cylinder, Ellipsoid, Ground, cast, rot_z
from .sensors import Sensor, make_sensor

PRESETS = {
    # name: (scene kind, sensor, speed m/s, frames[, acceleration m/s^2 from rest; none: at speed])
    "street-vlp16": ("street", "vlp16", 6.0, 120),
    "yard-vlp16": ("yard", "vlp16", 1.4, 120),
    "street-hdl64": ("street", "hdl64e", 6.0, 120),
    "yard-hdl64": ("yard", "hdl64e", 1.4, 120),
    # the HDL-64E street from rest, 6 m/s after 2 s (a car pulling away)
    "street-hdl64-start": ("street", "hdl64e", 6.0, 120, 3.0),
    # the street seen by an OS1-128-like sensor, as ouster-ros publishes it (OUSTER_LAYOUT)
    "street-os128": ("street", "os128", 6.0, 120),
}

# Packed XYZIRT as velodyne_pointcloud publishes it: unorganized, no-returns dropped.
VELODYNE_LAYOUT = [("x", 0, "<f4"), ("y", 4, "<f4"), ("z", 8, "<f4"), ("intensity", 12, "<f4"),
                   ("ring", 16, "<u2"), ("time", 18, "<f4")]
# ouster-ros PointOS (48 bytes): organized, one row per beam, the top beam's first (ring 0),
# no-returns NaN; `t` in ns after the stamp, `range` in mm.
OUSTER_LAYOUT = [("x", 0, "<f4"), ("y", 4, "<f4"), ("z", 8, "<f4"), ("intensity", 16, "<f4"),
                 ("t", 20, "<u4"), ("reflectivity", 24, "<u2"), ("ring", 26, "<u2"), ("ambient", 28, "<u2"),
                 ("range", 32, "<u4")]
OUSTER_POINT_STEP = 48


def make_hdl64e():
    """HDL-64E S2 layout (as in KITTI): upper block +2.0 .. -8.33 deg in 1/3 deg steps, lower
    block -8.83 .. -24.33 deg in 1/2 deg steps; the two blocks fire together, 0.17 deg columns at
    10 Hz. (sensors.py's "hdl64" spaces the beams evenly; A-LOAM's scan numbering assumes this
    layout.)"""
    upper = 2.0 - np.arange(32) / 3.0
    lower = -8.83 - 0.5 * np.arange(32)
    elev = np.empty(64)
    elev[0::2], elev[1::2] = upper, lower
    return Sensor("hdl64e", elev, 1.0e-6, 0.1 / 2083, 600.0, 120.0, 0.9, False)


def sensor_for(name):
    return make_hdl64e() if name == "hdl64e" else make_sensor(name)


# ---------------------------------------------------------------- path
@dataclass
class Path:
    """Planar path: straights and arcs, sampled densely; pose(t) interpolates by arc length."""
    s: np.ndarray      # arc length of the samples
    xy: np.ndarray     # (n, 2)
    yaw: np.ndarray    # heading
    speed: float
    wobble: float      # roll / pitch amplitude [rad]
    bounce: float      # height oscillation [m]
    bounce_hz: float
    accel: float = 0.0  # from rest at this acceleration up to `speed`; 0: at speed from t = 0

    @staticmethod
    def build(segments, speed, wobble, bounce, bounce_hz, step=0.02, accel=0.0):
        """segments: [("line", length) | ("arc", radius, angle_rad (+ = left))]."""
        x, y, h, s = 0.0, 0.0, 0.0, 0.0
        S, XY, H = [0.0], [(0.0, 0.0)], [0.0]
        for seg in segments:
            if seg[0] == "line":
                n = max(1, int(np.ceil(seg[1] / step)))
                for _ in range(n):
                    ds = seg[1] / n
                    x, y, s = x + ds * np.cos(h), y + ds * np.sin(h), s + ds
                    S.append(s); XY.append((x, y)); H.append(h)
            else:
                r, ang = seg[1], seg[2]
                length = abs(r * ang)
                n = max(1, int(np.ceil(length / step)))
                for _ in range(n):
                    ds = length / n
                    dh = np.sign(ang) * ds / r
                    hm = h + dh / 2  # chord at the mid heading: exact on a circle
                    chord = 2 * r * np.sin(abs(dh) / 2)
                    x, y, h, s = x + chord * np.cos(hm), y + chord * np.sin(hm), h + dh, s + ds
                    S.append(s); XY.append((x, y)); H.append(h)
        return Path(np.array(S), np.array(XY), np.unwrap(np.array(H)), speed, wobble, bounce, bounce_hz, accel)

    def distance(self, t):
        """Arc length covered at times t [s]."""
        t = np.asarray(t, float)
        if self.accel <= 0:
            return self.speed * t
        ta = self.speed / self.accel
        return np.where(t < ta, 0.5 * self.accel * t * t, 0.5 * self.speed * ta + self.speed * (t - ta))

    def pose(self, t):
        """Rotation (..., 3, 3) and position (..., 3) of the sensor at times t [s] (frame 0 at t=0),
        in the scene frame (the path starts at the origin heading +x)."""
        t = np.asarray(t, float)
        s = np.clip(self.distance(t), 0, self.s[-1])
        x = np.interp(s, self.s, self.xy[:, 0])
        y = np.interp(s, self.s, self.xy[:, 1])
        yaw = np.interp(s, self.s, self.yaw)
        w = 2 * np.pi * self.bounce_hz
        roll = self.wobble * np.sin(w * t * 0.5 + 0.3)
        pitch = self.wobble * 0.7 * np.sin(w * t * 0.37 + 1.1)
        z = self.bounce * np.sin(w * t)
        R = _rpy(roll, pitch, yaw)
        return R, np.stack([x, y, z], axis=-1)


def _rpy(roll, pitch, yaw):
    cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                              np.cos(yaw), np.sin(yaw))
    R = np.empty(np.shape(yaw) + (3, 3))
    R[..., 0, 0] = cy * cp
    R[..., 0, 1] = cy * sp * sr - sy * cr
    R[..., 0, 2] = cy * sp * cr + sy * sr
    R[..., 1, 0] = sy * cp
    R[..., 1, 1] = sy * sp * sr + cy * cr
    R[..., 1, 2] = sy * sp * cr - cy * sr
    R[..., 2, 0] = -sp
    R[..., 2, 1] = cp * sr
    R[..., 2, 2] = cp * cr
    return R


def make_path(kind, speed, duration, accel=0.0):
    if kind == "street":
        # 30 m straight, a right turn (radius 12 m), then straight on: a car at `speed`
        segs = [("line", 30.0), ("arc", 12.0, -np.pi / 2), ("line", 60.0)]
        p = Path.build(segs, speed, np.radians(0.4), 0.01, 1.5, accel=accel)
    else:
        # a walk around a courtyard: left turns of radius 2 m (handheld / backpack sensor)
        segs = [("line", 5.0), ("arc", 2.0, np.pi / 2), ("line", 4.0), ("arc", 2.0, np.pi / 2),
                ("line", 4.0), ("arc", 2.0, np.pi / 2), ("line", 10.0)]
        p = Path.build(segs, speed, np.radians(1.5), 0.03, 1.8, accel=accel)
    assert p.s[-1] >= p.distance(duration), "path shorter than the sequence"
    return p


# ---------------------------------------------------------------- scenes
def _dist_to_path(path, pts):
    pts = np.atleast_2d(pts)
    d = np.linalg.norm(pts[:, None, :] - path.xy[None, ::10, :], axis=2)
    return d.min(axis=1)


def _frame_at(path, s):
    i = min(np.searchsorted(path.s, s), len(path.s) - 1)
    return path.xy[i], path.yaw[i]


def sequence_scene(kind, path, seed, height):
    """Shapes along the path, each with its (x, y) centre and radius for culling."""
    rng = np.random.default_rng(seed)
    g = -height
    out = [(Ground(g), None, np.inf)]

    def add(shape, cx, cy, r):
        out.append((shape, np.array([cx, cy]), r))

    street = kind == "street"
    half_road = 6.0 if street else 1.5   # free corridor either side of the path
    walk, kerb = (4.0, 0.15) if street else (0.0, 0.0)
    length = path.s[-1]
    # buildings both sides, oriented along the local heading, dropped where they would reach
    # into the corridor (the inside of turns)
    for side in ((-1, 1) if street else ()):
        s = -15.0
        while s < length + 15.0:
            width = rng.uniform(8, 20) if street else rng.uniform(5, 12)
            sm = min(max(s + width / 2, 0.0), length)
            (px, py), h = _frame_at(path, sm)
            over = s + width / 2 - sm  # beyond the ends: extend straight
            px, py = px + over * np.cos(h), py + over * np.sin(h)
            setback = half_road + walk + (rng.uniform(0.0, 3.0) if street else rng.uniform(6.0, 10.0))
            depth = 10.0
            hgt = rng.uniform(5, 15) if street else rng.uniform(6, 12)
            nx, ny = -np.sin(h) * side, np.cos(h) * side
            cx, cy = px + nx * (setback + depth / 2), py + ny * (setback + depth / 2)
            R = rot_z(h)
            corners = np.array([[cx, cy]]) + (np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]]) *
                                              [width / 2, depth / 2]) @ R[:2, :2].T
            clear = half_road + walk + 0.3
            if _dist_to_path(path, np.vstack([corners, [[cx, cy]]])).min() > clear:
                add(Box((cx, cy, g + hgt / 2), (width / 2, depth / 2, hgt / 2), R, role="building"),
                    cx, cy, np.hypot(width, depth) / 2)
                if rng.random() < 0.5:  # a projection / recess on the facade
                    w2 = rng.uniform(2, width / 2)
                    off = rng.uniform(-width / 4, width / 4)
                    d2 = rng.uniform(0.6, 1.5)
                    qx, qy = cx + np.cos(h) * off - nx * (depth / 2 + d2 / 2), cy + np.sin(h) * off - ny * (depth / 2 + d2 / 2)
                    if _dist_to_path(path, [[qx, qy]]).min() > clear:
                        add(Box((qx, qy, g + hgt * 0.35), (w2 / 2, d2 / 2, hgt * 0.35), R, role="building"),
                            qx, qy, w2)
            s += width + (rng.uniform(0.0, 5.0) if street else rng.uniform(0.0, 2.0))
    if not street:
        # the courtyard's enclosure: facades on the four sides of the walk's bounding box, each
        # side a row of buildings with recesses, a gap or two for passages
        lo, hi = path.xy.min(axis=0), path.xy.max(axis=0)
        margin = rng.uniform(6.0, 9.0, 4)
        x0, x1, y0, y1 = lo[0] - margin[0], hi[0] + margin[1], lo[1] - margin[2], hi[1] + margin[3]
        depth = 10.0
        for (ax, a0, a1, fixed, outward) in ((0, x0 - 10, x1 + 10, y0, -1), (0, x0 - 10, x1 + 10, y1, 1),
                                             (1, y0, y1, x0, -1), (1, y0, y1, x1, 1)):
            a = a0
            while a < a1:
                w = min(rng.uniform(5.0, 12.0), a1 - a)
                if rng.random() < 0.12:  # a passage
                    a += w
                    continue
                rec = rng.uniform(-0.5, 1.5)
                hgt = rng.uniform(6, 15)
                mid = fixed + outward * (rec + depth / 2)
                c = (a + w / 2, mid) if ax == 0 else (mid, a + w / 2)
                half = (w / 2, depth / 2) if ax == 0 else (depth / 2, w / 2)
                add(Box((c[0], c[1], g + hgt / 2), (half[0], half[1], hgt / 2), role="building"),
                    c[0], c[1], np.hypot(*half))
                a += w
    if street:
        i = np.searchsorted(path.s, 30.0 + 12.0 * np.pi / 4)  # the middle of the turn
        (px, py), h = path.xy[i], path.yaw[i]
        for extra in (0.0, 14.0):
            off = half_road + walk + 2.0 + extra + 6.0
            cx, cy = px - np.sin(h) * off, py + np.cos(h) * off  # outer side of a right turn: left
            add(Box((cx, cy, g + 6.0), (6.0, 6.0, 6.0 + extra / 3), rot_z(h), role="building"), cx, cy, 8.5)
    # pavements along the straights of the street (kerb faces the road)
    if street:
        for s0, s1 in ((-15.0, 28.0), (length - 58.0, length + 15.0)):
            sm = 0.5 * (s0 + s1)
            (px, py), h = _frame_at(path, min(max(sm, 0), length))
            over = sm - min(max(sm, 0), length)
            px, py = px + over * np.cos(h), py + over * np.sin(h)
            for side in (-1, 1):
                nx, ny = -np.sin(h) * side, np.cos(h) * side
                off = half_road + walk / 2
                add(Box((px + nx * off, py + ny * off, g + kerb / 2), ((s1 - s0) / 2, walk / 2, kerb / 2), rot_z(h),
                        role="pavement"), px + nx * off, py + ny * off, (s1 - s0) / 2)
    top = g + kerb
    n_obj = int(length / (6.0 if street else 2.0))
    for _ in range(n_obj):
        s = rng.uniform(0, length)
        (px, py), h = _frame_at(path, s)
        side = rng.choice((-1, 1))
        nx, ny = -np.sin(h) * side, np.cos(h) * side
        what = rng.random()
        if what < 0.3:  # parked car
            off = rng.uniform(2.8, half_road - 1.0) if street else rng.uniform(3.0, 6.0)
            cx, cy = px + nx * off, py + ny * off
            if _dist_to_path(path, [[cx, cy]]).min() < off - 0.5:
                continue
            yaw = h + rng.normal(0, 0.08)
            add(Box((cx, cy, g + 0.65), (2.1, 0.9, 0.35), rot_z(yaw), role="car_body"), cx, cy, 2.5)
            add(Ellipsoid((cx - 0.2 * np.cos(yaw), cy - 0.2 * np.sin(yaw), g + 1.0), (1.4, 0.85, 0.55), yaw,
                          role="car_cabin"), cx, cy, 1.5)
        elif what < 0.6:  # pole
            off = half_road + rng.uniform(0.4, 1.0) if street else rng.uniform(2.0, 7.0)
            cx, cy = px + nx * off, py + ny * off
            if _dist_to_path(path, [[cx, cy]]).min() < 1.0:
                continue
            add(Cylinder(cx, cy, rng.uniform(0.06, 0.2), top, g + rng.uniform(3, 7)), cx, cy, 0.3)
        elif what < 0.8:  # tree
            off = half_road + rng.uniform(1.5, 3.0) if street else rng.uniform(3.0, 8.0)
            cx, cy = px + nx * off, py + ny * off
            if _dist_to_path(path, [[cx, cy]]).min() < 2.5:
                continue
            trunk, crown = rng.uniform(2.0, 3.0), rng.uniform(1.5, 2.5)
            add(Cylinder(cx, cy, rng.uniform(0.12, 0.3), top, top + trunk, role="trunk"), cx, cy, 0.3)
            add(Ellipsoid((cx, cy, top + trunk + crown * 0.8), (crown, crown, crown * 0.9),
                          density=rng.uniform(1.5, 4.0), role="tree_crown"), cx, cy, crown)
        else:  # box: bench, bin, planter, electrical cabinet
            off = half_road + rng.uniform(0.5, walk - 0.5) if street else rng.uniform(2.0, 7.0)
            cx, cy = px + nx * off, py + ny * off
            if _dist_to_path(path, [[cx, cy]]).min() < 1.5:
                continue
            hh = rng.uniform(0.3, 0.8, 3)
            add(Box((cx, cy, top + hh[2]), hh, rot_z(h + rng.uniform(-0.3, 0.3)), role="box"), cx, cy, 1.2)
    return out


# ---------------------------------------------------------------- frames
def simulate_sequence_frame(sensor, path, shapes, k, noise_sigma, rng, cull=None):
    """One sweep k: points in the sensor frame at their firing times, in driver order: column by
    column, lasers in firing order, no-returns dropped; for an organized sensor, row by row from
    the top beam (ring 0, as ouster-ros numbers them), no-returns NaN."""
    n_b, n_c = sensor.n_beams, sensor.n_columns
    period = 60.0 / sensor.rpm
    t_rel = np.arange(n_c)[None, :] * sensor.block_period + np.arange(n_b)[:, None] * sensor.firing_dt
    t_abs = k * period + t_rel
    az = np.radians(180.0 - 360.0 / period * t_rel)  # clockwise from behind
    el = np.radians(np.broadcast_to(sensor.elevation_deg[:, None], (n_b, n_c)))
    ds = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)
    # pose per column (lasers of a column fire within microseconds: use the column's time)
    Rc, pc = path.pose(k * period + np.arange(n_c) * sensor.block_period)
    dw = np.einsum("cij,bcj->bci", Rc, ds)
    o = np.broadcast_to(pc[None, :, :], dw.shape)
    centre = path.pose(k * period + period / 2)[1][:2]
    reach = cull if cull is not None else sensor.max_range
    use = [s for s, c, r in shapes if c is None or np.linalg.norm(c - centre) - r < reach]
    t, _, _, _, kind = cast(use, o.reshape(-1, 3), dw.reshape(-1, 3))
    t, kind = t.reshape(n_b, n_c), kind.reshape(n_b, n_c)
    valid = np.isfinite(t) & (t >= sensor.min_range) & (t <= sensor.max_range)
    meas = t + rng.normal(0.0, noise_sigma, t.shape) if noise_sigma > 0 else t
    xyz = ds * np.where(valid, meas, np.nan)[..., None]
    base = np.select([kind == 1, kind == 5, kind == 4], [40.0, 70.0, 15.0], 0.0)
    inten = np.clip(base + rng.normal(0, 3.0, t.shape), 0, 255)
    ring = np.broadcast_to(sensor.ring[:, None], (n_b, n_c))
    if sensor.organized:
        rows = np.argsort(-sensor.elevation_deg, kind="stable")  # top beam first
        t_ns = np.round(np.broadcast_to(t_rel, (n_b, n_c)) * 1e9)
        return {"x": xyz[rows, :, 0].reshape(-1), "y": xyz[rows, :, 1].reshape(-1), "z": xyz[rows, :, 2].reshape(-1),
                "intensity": np.where(valid, inten, 0.0)[rows].reshape(-1), "t": t_ns[rows].reshape(-1),
                "ring": np.repeat(np.arange(n_b), n_c), "reflectivity": 0, "ambient": 0,
                "range": np.where(valid, np.round(meas * 1000.0), 0.0)[rows].reshape(-1)}
    keep = valid.T.reshape(-1)
    flat = lambda a, w=None: np.swapaxes(a, 0, 1).reshape((-1, 3) if w else (-1,))[keep]  # noqa: E731
    xyz = flat(xyz, 3)
    return {"x": xyz[:, 0], "y": xyz[:, 1], "z": xyz[:, 2], "intensity": flat(inten),
            "ring": flat(ring), "time": flat(t_rel)}


def ground_truth_tum(path, frames, period, stamps):
    """TUM lines: sensor pose at each stamp (first firing) in the LiDAR frame of frame 0."""
    R, p = path.pose(np.arange(frames) * period)
    R0, p0 = R[0], p[0]
    lines = []
    for k in range(frames):
        Rk = R0.T @ R[k]
        tk = R0.T @ (p[k] - p0)
        q = _quat(Rk)
        lines.append("%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f" % ((stamps[k],) + tuple(tk) + tuple(q)))
    return lines


def _quat(R):
    """(qx, qy, qz, qw) of a rotation matrix."""
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    q = np.array([x, y, z, w])
    return q / np.linalg.norm(q)


def generate(name, bag_path, tum_path, seed=1, frames=None, noise=0.01, height=1.8, progress=None):
    """Writes the sequence preset `name` (PRESETS) as a bag of clouds on /velodyne_points (frame
    velodyne; packed XYZIRT, or ouster-ros PointOS for an organized sensor) and its ground truth
    as TUM. Deterministic from seed."""
    import rosbag
    import rospy
    from std_msgs.msg import Header

    from .cloud_io import make_cloud

    kind, sensor_name, speed, n_default = PRESETS[name][:4]
    accel = PRESETS[name][4] if len(PRESETS[name]) > 4 else 0.0
    frames = frames or n_default
    sensor = sensor_for(sensor_name)
    period = 60.0 / sensor.rpm
    path = make_path(kind, speed, frames * period + 0.2, accel)
    shapes = sequence_scene(kind, path, seed, height)
    layout, step = (OUSTER_LAYOUT, OUSTER_POINT_STEP) if sensor.organized else (VELODYNE_LAYOUT, None)
    t0 = 1.6e9
    stamps = [t0 + k * period for k in range(frames)]
    tmp = bag_path + ".part"
    with rosbag.Bag(tmp, "w") as bag:
        for k in range(frames):
            rng = np.random.default_rng([seed, k])
            vrng = np.random.default_rng([seed, k, 1])
            for s, _, _ in shapes:
                if getattr(s, "density", None):
                    s.rng = vrng
            pts = simulate_sequence_frame(sensor, path, shapes, k, noise, rng)
            stamp = rospy.Time.from_sec(stamps[k])
            rows = sensor.n_beams if sensor.organized else 1
            msg = make_cloud(pts, layout, Header(seq=k, stamp=stamp, frame_id="velodyne"), rows, len(pts["x"]) // rows,
                             itemsize=step)
            bag.write("/velodyne_points", msg, stamp)
            if progress:
                progress(k, len(pts["x"]))
    with open(tum_path, "w") as f:
        f.write("# %s seed %d: sensor pose at each stamp in the LiDAR frame of frame 0 "
                "(stamp tx ty tz qx qy qz qw)\n" % (name, seed))
        f.write("\n".join(ground_truth_tum(path, frames, period, stamps)) + "\n")
    import os
    os.replace(tmp, bag_path)
    return {"name": name, "sensor": sensor.name, "scene": kind, "speed": speed, "frames": frames,
            "shapes": len(shapes), "path_length": float(path.distance((frames - 1) * period))}
