"""Vectorised ray casting against the analytic shapes the scene simulator builds scenes from.

Every shape answers `intersect(o, d)` for N rays at once (o, d: (N, 3), d unit) with
(t, face, normal): distance along the ray (inf where missed), a face id, and the unit surface
normal. A surface is identified by (shape index, face id): ground truth calls two neighbouring
samples "the same surface" exactly when these agree, so a face id must change wherever the
surface folds (box faces) or changes kind (cylinder side vs cap).
"""
import numpy as np

INF = np.inf
EPS = 1e-6

# Surface kinds, which the ground truth maps to classes.
PLANAR, CURVED, VEGETATION = 1, 5, 4
# Widest object the ground truth calls thin (a pole, trunk or sign seen as a narrow run bounded by
# depth jumps on both sides): the core's default thin_max_width.
THIN_MAX_WIDTH = 0.7


def rot_z(yaw):
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(pitch):
    c, s = np.cos(pitch), np.sin(pitch)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


class Ground:
    """Infinite horizontal plane z = z0, seen from above."""
    kind_name = "ground"

    def __init__(self, z0):
        self.z0 = float(z0)

    def kind(self, face):
        return np.full(face.shape, PLANAR)

    def intersect(self, o, d):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.z0 - o[:, 2]) / d[:, 2]
        t = np.where((d[:, 2] < -EPS) & (t > EPS), t, INF)
        n = np.zeros_like(o)
        n[:, 2] = 1.0
        return t, np.zeros(len(o), dtype=np.int64), n

    def describe(self):
        return {"type": "ground", "z": self.z0}


class Box:
    """Oriented box: centre c, rotation R (columns = local axes), half extents h.
    Faces 0..5 = -x, +x, -y, +y, -z, +z in the local frame: every face is planar."""
    kind_name = "box"

    def __init__(self, c, h, R=np.eye(3), role="box", thin=False):
        self.c, self.h, self.R, self.role = np.asarray(c, float), np.asarray(h, float), R, role
        self.thin = thin  # a sign plate: narrow from every side (ground truth: thin object)

    def kind(self, face):
        return np.full(face.shape, PLANAR)

    def intersect(self, o, d):
        lo = (o - self.c) @ self.R
        ld = d @ self.R
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (-self.h - lo) / ld
            t2 = (self.h - lo) / ld
        tmin = np.where(np.isnan(t1), -INF, np.minimum(t1, t2))
        tmax = np.where(np.isnan(t1), INF, np.maximum(t1, t2))
        # a ray parallel to a slab and outside it never enters
        outside = (np.abs(ld) < EPS) & (np.abs(lo) > self.h)
        tmin = np.where(outside, INF, tmin)
        tmax = np.where(outside, -INF, tmax)
        rows = np.arange(len(o))
        axis = np.argmax(tmin, axis=1)
        tnear = tmin[rows, axis]
        exit_axis = np.argmin(tmax, axis=1)
        tfar = tmax[rows, exit_axis]
        # from outside, the face the ray enters; from inside (a room), the face it leaves by
        inside = (tnear <= EPS) & (tfar > EPS)
        axis = np.where(inside, exit_axis, axis)
        t = np.where((tnear <= tfar) & (tnear > EPS), tnear, np.where(inside, tfar, INF))
        sign = -np.sign(ld[rows, axis])  # the normal faces the ray
        face = 2 * axis + np.where(inside, sign < 0, sign > 0)
        n = self.R[:, axis].T * sign[:, None]
        return t, face, n

    def describe(self):
        out = {"type": "box", "role": self.role, "centre": self.c.tolist(),
               "half_extents": self.h.tolist(), "rotation": self.R.tolist()}
        if self.thin:
            out["thin"] = True
        return out


class Cylinder:
    """Vertical cylinder (pole, trunk): face 0 = curved side, face 1 = flat top cap."""
    kind_name = "cylinder"

    def __init__(self, cx, cy, r, z0, z1, role="pole"):
        self.cx, self.cy, self.r, self.z0, self.z1, self.role = cx, cy, r, z0, z1, role
        self.thin = 2 * r <= THIN_MAX_WIDTH  # poles, trunks, sign posts (ground truth: thin object)

    def kind(self, face):
        return np.where(face == 0, CURVED, PLANAR)

    def intersect(self, o, d):
        ox, oy = o[:, 0] - self.cx, o[:, 1] - self.cy
        a = d[:, 0] ** 2 + d[:, 1] ** 2
        b = 2 * (ox * d[:, 0] + oy * d[:, 1])
        cc = ox ** 2 + oy ** 2 - self.r ** 2
        disc = b * b - 4 * a * cc
        with np.errstate(invalid="ignore", divide="ignore"):
            ts = (-b - np.sqrt(disc)) / (2 * a)
        z = o[:, 2] + ts * d[:, 2]
        side = (disc > 0) & (a > EPS) & (ts > EPS) & (z >= self.z0) & (z <= self.z1)
        t_side = np.where(side, ts, INF)
        with np.errstate(invalid="ignore", divide="ignore"):
            tc = (self.z1 - o[:, 2]) / d[:, 2]
        px, py = ox + tc * d[:, 0], oy + tc * d[:, 1]
        cap = (d[:, 2] < -EPS) & (tc > EPS) & (px ** 2 + py ** 2 <= self.r ** 2)
        t_cap = np.where(cap, tc, INF)
        t = np.minimum(t_side, t_cap)
        face = np.where(t_cap < t_side, 1, 0)
        p = o + np.where(np.isfinite(t), t, 0)[:, None] * d
        n = np.zeros_like(o)
        n[:, 0], n[:, 1] = (p[:, 0] - self.cx) / self.r, (p[:, 1] - self.cy) / self.r
        n[face == 1] = (0.0, 0.0, 1.0)
        return t, face, n

    def describe(self):
        return {"type": "cylinder", "role": self.role, "centre_xy": [self.cx, self.cy],
                "radius": self.r, "z": [self.z0, self.z1], "thin": bool(self.thin)}


class Ellipsoid:
    """Ellipsoid with semi-axes a, yawed. Solid (car cabin: curved surface) or, with a
    density, a vegetation volume: a ray entering it returns at an exponentially distributed
    free path (mean 1 / density) if that falls before it leaves, else passes through."""
    kind_name = "ellipsoid"

    def __init__(self, c, a, yaw=0.0, density=None, role="cabin"):
        self.c, self.a, self.R = np.asarray(c, float), np.asarray(a, float), rot_z(yaw)
        self.density, self.role = density, role
        self.rng = None  # set by the scene for vegetation, so draws follow the seed

    def kind(self, face):
        return np.full(face.shape, VEGETATION if self.density else CURVED)

    def _span(self, o, d):
        lo = ((o - self.c) @ self.R) / self.a
        ld = (d @ self.R) / self.a
        a = np.sum(ld * ld, axis=1)
        b = 2 * np.sum(lo * ld, axis=1)
        cc = np.sum(lo * lo, axis=1) - 1
        disc = b * b - 4 * a * cc
        sq = np.sqrt(np.maximum(disc, 0))
        return (-b - sq) / (2 * a), (-b + sq) / (2 * a), disc > 0

    def intersect(self, o, d):
        t0, t1, ok = self._span(o, d)
        if self.density:
            t0 = np.maximum(t0, EPS)
            free = self.rng.exponential(1.0 / self.density, len(o))
            th = t0 + free
            t = np.where(ok & (t1 > EPS) & (th < t1), th, INF)
        else:
            t = np.where(ok & (t0 > EPS), t0, INF)
        p = o + np.where(np.isfinite(t), t, 0)[:, None] * d
        g = (((p - self.c) @ self.R) / self.a ** 2) @ self.R.T
        n = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), EPS)
        return t, np.zeros(len(o), dtype=np.int64), n

    def describe(self):
        out = {"type": "ellipsoid", "role": self.role, "centre": self.c.tolist(),
               "semi_axes": self.a.tolist(), "yaw": float(np.arctan2(self.R[1, 0], self.R[0, 0]))}
        if self.density:
            out["density_per_m"] = self.density
        return out


class Hedge:
    """Vegetation volume shaped as an oriented box (a hedge along a pavement): a ray entering it
    returns at an exponentially distributed free path (mean 1 / density) if that falls before it
    leaves, else passes through. Foliage: no faces, face id 0, normal of the box face entered."""
    kind_name = "hedge"

    def __init__(self, c, h, R=np.eye(3), density=8.0, role="hedge"):
        self.box = Box(c, h, R, role)
        self.density, self.role = density, role
        self.rng = None

    def kind(self, face):
        return np.full(face.shape, VEGETATION)

    def intersect(self, o, d):
        b = self.box
        lo, ld = (o - b.c) @ b.R, d @ b.R
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (-b.h - lo) / ld, (b.h - lo) / ld
        tmin = np.where(np.isnan(t1), -INF, np.minimum(t1, t2))
        tmax = np.where(np.isnan(t1), INF, np.maximum(t1, t2))
        outside = (np.abs(ld) < EPS) & (np.abs(lo) > b.h)
        tmin, tmax = np.where(outside, INF, tmin), np.where(outside, -INF, tmax)
        t0, t1 = np.max(tmin, axis=1), np.min(tmax, axis=1)
        t0 = np.maximum(t0, EPS)
        th = t0 + self.rng.exponential(1.0 / self.density, len(o))
        t = np.where((t0 < t1) & (th < t1), th, INF)
        n = np.zeros_like(o)
        n[:, 2] = 1.0
        return t, np.zeros(len(o), dtype=np.int64), n

    def describe(self):
        out = self.box.describe()
        out.update(type="hedge", density_per_m=self.density)
        return out


SHELL = 0.55  # a crown's foliage clumps fill the outer shell of its envelope, from this fraction out


class Canopy:
    """A tree crown as foliage clumps: spheres of radius `clump_radius` whose centres fill an
    ellipsoid envelope (semi-axes a). Inside a clump a ray returns at an exponentially
    distributed free path (mean 1 / density); between clumps it flies on. Returns thus come from
    anywhere in the crown's depth (range spread of tens of cm between neighbouring beams), the
    neighbouring beams of a clump are correlated as leaves on a branch are, and some rays pass
    through gaps to the trunk, branches or whatever stands behind. Clump positions come from the
    scene's rng (the seed); the free paths from the vegetation rng."""
    kind_name = "canopy"

    def __init__(self, c, a, rng, clump_radius=0.5, cover=2.5, density=6.0, role="tree_crown"):
        self.c, self.a = np.asarray(c, float), np.asarray(a, float)
        self.r, self.density, self.role = float(clump_radius), float(density), role
        # cover = clumps crossed by a ray through the middle, on average: n pi r^2 times the
        # length of shell it crosses, 2 a (1 - SHELL), over the shell's volume 4/3 pi a^3 (1 - SHELL^3)
        ab = self.a[0] * self.a[1]
        n = max(int(round(cover * 2.0 * (1 - SHELL ** 3) * ab / (3.0 * (1 - SHELL) * self.r ** 2))), 1)
        u = rng.normal(size=(n, 3))
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        # uniform in the outer shell of the envelope (0.55-1 of it, out to half a clump radius
        # inside): leaves grow where the light is, the inside holds the trunk and the branches
        rad = (SHELL ** 3 + rng.random(n) * (1 - SHELL ** 3)) ** (1.0 / 3.0)
        self.centres = self.c + u * rad[:, None] * np.maximum(self.a - 0.5 * self.r, 0.1)
        self.rng = None

    def kind(self, face):
        return np.full(face.shape, VEGETATION)

    def intersect(self, o, d):
        t = np.full(len(o), INF)
        n = np.zeros_like(o)
        n[:, 2] = 1.0
        # rays that meet the envelope grown by a clump radius (a quadric test)
        a = self.a + self.r
        lo, ld = (o - self.c) / a, d / a
        qa, qb, qc = np.sum(ld * ld, 1), 2 * np.sum(lo * ld, 1), np.sum(lo * lo, 1) - 1
        disc = qb * qb - 4 * qa * qc
        sel = np.nonzero((disc > 0) & ((-qb + np.sqrt(np.maximum(disc, 0))) > 0))[0]
        free = self.rng.exponential(1.0 / self.density, (len(sel), len(self.centres)))
        if len(sel) == 0:
            return t, np.zeros(len(o), dtype=np.int64), n
        oo, dd = o[sel], d[sel]
        rel = oo[:, None, :] - self.centres[None, :, :]
        b = np.einsum("nkj,nj->nk", rel, dd)
        cc = np.sum(rel * rel, axis=2) - self.r ** 2
        disc = b * b - cc
        sq = np.sqrt(np.maximum(disc, 0))
        t0, t1 = np.maximum(-b - sq, EPS), -b + sq
        th = t0 + free
        th = np.where((disc > 0) & (t1 > EPS) & (th < t1), th, INF)
        k = np.argmin(th, axis=1)
        best = th[np.arange(len(sel)), k]
        t[sel] = best
        p = oo + np.where(np.isfinite(best), best, 0)[:, None] * dd
        g = p - self.centres[k]
        n[sel] = g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), EPS)
        return t, np.zeros(len(o), dtype=np.int64), n

    def describe(self):
        return {"type": "canopy", "role": self.role, "centre": self.c.tolist(), "semi_axes": self.a.tolist(),
                "clump_radius": self.r, "clumps": len(self.centres), "density_per_m": self.density}


def cast(shapes, o, d, solid_only=False):
    """Nearest hit over all shapes: (t, shape index, face, normal, kind); index -1 = no hit.
    solid_only skips vegetation (ground-truth geometry must not depend on random draws)."""
    n = len(o)
    best_t = np.full(n, INF)
    best_s = np.full(n, -1, dtype=np.int64)
    best_f = np.zeros(n, dtype=np.int64)
    best_n = np.zeros((n, 3))
    best_k = np.zeros(n, dtype=np.int64)
    for i, s in enumerate(shapes):
        if solid_only and getattr(s, "density", None):
            continue
        t, f, nn = s.intersect(o, d)
        closer = t < best_t
        best_t[closer], best_s[closer], best_f[closer] = t[closer], i, f[closer]
        best_n[closer] = nn[closer]
        best_k[closer] = s.kind(f)[closer]
    return best_t, best_s, best_f, best_n, best_k
