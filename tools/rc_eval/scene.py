"""Random street scenes, fully determined by a seed: ground, kerbed pavements, box buildings
with recessed facades, cars (box body + rounded cabin), poles, signs (a thin post carrying a
plate, turned at random so that some are seen edge-on), an inclined ramp (a gentle and a steep
one), trees (a trunk rising into a crown of foliage clumps, raycast.Canopy), bushes and hedges
(dense vegetation volumes; hedges are long boxes along the facades). The sensor sits at the
origin, `height` metres above the ground, looking along the street (+x).

Foliage returns come from inside the volumes: in a crown, from any clump (0.25-0.45 m radius) a
ray meets in the crown's outer shell (mean free path 1 / density = 12-25 cm inside a clump), so
the returns lie a median ~0.5 m inside the crown's envelope (10th-90th percentile ~0.1-1.5 m)
and 10-20 % of the rays pass through gaps to the trunk or what stands behind; in bushes and
hedges, 8-17 cm deep on average (exponential free path)."""
import numpy as np

from .raycast import Box, Canopy, Cylinder, Ellipsoid, Ground, Hedge, rot_y, rot_z


def street_scene(seed, height=1.8, kind="street"):
    rng = np.random.default_rng(seed)
    g = -height
    shapes = [Ground(g)]
    if kind == "box":
        # A calibration scene: ground and a few boxes only (creases and depth jumps, no clutter).
        for _ in range(4):
            r, a = rng.uniform(6, 14), rng.uniform(0, 2 * np.pi)
            h = rng.uniform(0.8, 2.5, 3)
            shapes.append(Box((r * np.cos(a), r * np.sin(a), g + h[2]), h, rot_z(rng.uniform(0, np.pi)),
                              role="box"))
        return shapes
    half_road = rng.uniform(5.0, 7.0)
    walk = 4.0
    kerb = 0.15
    for side in (-1, 1):
        # pavement: its street-side face is the kerb
        shapes.append(Box((0, side * (half_road + walk / 2), g + kerb / 2), (70, walk / 2, kerb / 2),
                          role="pavement"))
        x = -50.0
        while x < 50.0:
            width = rng.uniform(8, 20)
            setback = half_road + walk + rng.uniform(0.0, 3.0)
            hgt = rng.uniform(5, 15)
            parts = rng.integers(1, 4)  # 2-3 parts = a facade with recesses / projections
            edges = np.sort(rng.uniform(0, width, parts - 1))
            xs = np.concatenate(([0.0], edges, [width])) + x
            for i in range(parts):
                sb = setback + (rng.uniform(-1.5, 1.5) if i > 0 else 0.0)
                sb = max(sb, half_road + walk + 0.3)
                depth = 10.0
                shapes.append(Box(((xs[i] + xs[i + 1]) / 2, side * (sb + depth / 2), g + hgt / 2),
                                  ((xs[i + 1] - xs[i]) / 2, depth / 2, hgt / 2), role="building"))
            x += width + rng.uniform(0.0, 5.0)
    top = g + kerb
    for _ in range(rng.integers(2, 6)):  # cars
        side = rng.choice((-1, 1))
        cx = rng.uniform(5, 35) * rng.choice((-1, 1))
        cy = side * rng.uniform(1.5, half_road - 1.2)
        yaw = rng.normal(0, 0.08)
        shapes.append(Box((cx, cy, g + 0.65), (2.1, 0.9, 0.35), rot_z(yaw), role="car_body"))
        shapes.append(Ellipsoid((cx - 0.2, cy, g + 1.0), (1.4, 0.85, 0.55), yaw, role="car_cabin"))
    for _ in range(rng.integers(3, 7)):  # poles on the pavement
        side = rng.choice((-1, 1))
        shapes.append(Cylinder(rng.uniform(-40, 40), side * (half_road + rng.uniform(0.4, 1.0)),
                               rng.uniform(0.06, 0.2), top, g + rng.uniform(3, 7)))
    for _ in range(rng.integers(2, 5)):  # trees: trunk up into the crown's middle, clumped crown
        side = rng.choice((-1, 1))
        tx, ty = rng.uniform(-40, 40), side * (half_road + rng.uniform(1.5, 3.0))
        trunk = rng.uniform(2.0, 3.0)
        crown = rng.uniform(1.5, 2.5)
        cz = top + trunk + crown * 0.8
        shapes.append(Cylinder(tx, ty, rng.uniform(0.12, 0.3), top, cz, role="trunk"))
        shapes.append(Canopy((tx, ty, cz), (crown, crown, crown * 0.9), rng,
                             clump_radius=rng.uniform(0.25, 0.45), cover=rng.uniform(1.5, 2.5),
                             density=rng.uniform(4.0, 8.0), role="tree_crown"))
    for _ in range(rng.integers(1, 4)):  # bushes along the facades
        side = rng.choice((-1, 1))
        shapes.append(Ellipsoid((rng.uniform(-30, 30), side * (half_road + walk - 0.8), top + 0.5),
                                (rng.uniform(1.0, 2.5), 0.8, 0.8), density=6.0, role="bush"))
    for _ in range(rng.integers(1, 4)):  # hedges: long dense boxes of foliage along the facades
        side = rng.choice((-1, 1))
        half = np.array([rng.uniform(1.5, 6.0), rng.uniform(0.25, 0.5), rng.uniform(0.4, 0.8)])
        shapes.append(Hedge((rng.uniform(-35, 35), side * (half_road + walk - half[1] - 0.1), top + half[2]),
                            half, density=rng.uniform(8.0, 12.0)))
    for _ in range(rng.integers(1, 4)):  # signs: a thin post carrying a plate, turned at random
        side = rng.choice((-1, 1))
        sx, sy = rng.uniform(-35, 35), side * (half_road + rng.uniform(0.3, 0.8))
        post_r, post_top = rng.uniform(0.03, 0.05), top + rng.uniform(2.2, 2.8)
        shapes.append(Cylinder(sx, sy, post_r, top, post_top, role="sign_post"))
        yaw = rng.uniform(0, np.pi)
        half = np.array([rng.uniform(0.2, 0.35), 0.015, rng.uniform(0.2, 0.4)])
        normal = np.array([-np.sin(yaw), np.cos(yaw), 0.0])  # the plate's local y, in front of the post
        c = np.array([sx, sy, post_top - 0.05]) + normal * (post_r + half[1] + 0.005)
        shapes.append(Box(c, half, rot_z(yaw), role="sign_plate", thin=True))
    for pitch_deg in (8.0, 25.0):  # ramps rising along +x: below / above the crease angle
        p = np.radians(pitch_deg)
        length, width, thick = 2.5, 1.5, 0.1
        cx = rng.uniform(8, 25) * rng.choice((-1, 1))
        cy = rng.uniform(-half_road + 2, half_road - 2)
        cz = g + length * np.sin(p) - thick * np.cos(p)
        shapes.append(Box((cx, cy, cz), (length, width, thick), rot_z(rng.uniform(-0.3, 0.3)) @ rot_y(-p),
                          role="ramp_%gdeg" % pitch_deg))
    return shapes


def seed_vegetation(shapes, rng):
    for s in shapes:
        if getattr(s, "density", None):
            s.rng = rng
