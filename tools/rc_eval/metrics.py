"""The paper's unsupervised metrics (section 5.3.1), on labelled clouds.

The paper names the metrics but not their constants; the choices here are stated once:
  Planarity score  1 / (mean over Plane components of the mean |point-to-plane distance| to a
                   RANSAC plane, in cm). In cm because a ~1 cm fit error then scores ~1, the
                   range of the paper's Table 2 (0.12 .. 0.93); the paper gives no unit.
                   RANSAC: 100 hypotheses, inlier band 5 cm, least-squares refit on inliers;
                   components with fewer than MIN_COMPONENT points are skipped.
  Feature purity   1 - mean over DBSCAN clusters (eps 0.5 m, min 5 points) of Edge and Corner
                   points of the entropy (base 2, so in [0, 1]) of the Edge/Corner label mix.
  Temporal stab.   frame B is registered onto frame A by point-to-plane ICP; the share of B's
                   labelled points whose nearest labelled A point (within 0.2 m) has the same label.
Components come from the cloud's `primitive` field (the core's connected components); when a
cloud has none (the baselines), Plane components are the connected components of Plane points
under the same DBSCAN-style radius graph.
"""
import numpy as np
from scipy.spatial import cKDTree

MIN_COMPONENT = 10
RANSAC_ITERS = 100
RANSAC_BAND = 0.05
DBSCAN_EPS = 0.5
DBSCAN_MIN = 5
MATCH_DIST = 0.2


def _xyz(a):
    p = np.stack([a["x"], a["y"], a["z"]], axis=1).astype(float)
    return p


def plane_fit_error(p, rng):
    """Mean |distance| of all points to the RANSAC plane (refit on its inliers)."""
    n = len(p)
    idx = rng.integers(0, n, (RANSAC_ITERS, 3))
    a, b, c = p[idx[:, 0]], p[idx[:, 1]], p[idx[:, 2]]
    normals = np.cross(b - a, c - a)
    norm = np.linalg.norm(normals, axis=1)
    ok = norm > 1e-9
    if not ok.any():
        return None
    normals = normals[ok] / norm[ok, None]
    d = np.abs(normals @ p.T - np.sum(normals * a[ok], axis=1)[:, None])
    best = np.argmax(np.sum(d < RANSAC_BAND, axis=1))
    inl = p[d[best] < RANSAC_BAND]
    if len(inl) < 3:
        inl = p
    centroid = inl.mean(axis=0)
    _, _, vt = np.linalg.svd(inl - centroid, full_matrices=False)
    normal = vt[-1]
    return float(np.mean(np.abs((p - centroid) @ normal)))


def _radius_components(p, eps, min_pts=1):
    """DBSCAN (min_pts >= 2: clusters of core points plus the border points they reach) or plain
    radius-graph components (min_pts = 1). Label -1 = noise."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    n = len(p)
    lab = np.full(n, -1, dtype=np.int64)
    if n == 0:
        return lab
    tree = cKDTree(p)
    pairs = tree.query_pairs(eps, output_type="ndarray")
    count = 1 + np.bincount(pairs.ravel(), minlength=n)  # neighbours including the point itself
    core = count >= min_pts
    cc = pairs[core[pairs[:, 0]] & core[pairs[:, 1]]]
    g = coo_matrix((np.ones(len(cc)), (cc[:, 0], cc[:, 1])), shape=(n, n))
    _, comp = connected_components(g, directed=False)
    lab[core] = comp[core]
    # border points join the cluster of a core neighbour
    for a, b in ((0, 1), (1, 0)):
        m = core[pairs[:, a]] & ~core[pairs[:, b]]
        lab[pairs[m, b]] = comp[pairs[m, a]]
    _, lab[lab >= 0] = np.unique(lab[lab >= 0], return_inverse=True)
    return lab


def planarity(a, seed=0):
    """(score, mean error [m], number of components)."""
    rng = np.random.default_rng(seed)
    ok = np.isfinite(a["x"]) & (a["label"] == 1)
    p = _xyz(a)[ok]
    if "primitive" in a.dtype.names:
        comp = a["primitive"][ok].astype(np.int64)
    else:
        comp = _radius_components(p, 0.3)
    errs = []
    for c in np.unique(comp[comp >= 0]):
        q = p[comp == c]
        if len(q) >= MIN_COMPONENT:
            e = plane_fit_error(q, rng)
            if e is not None:
                errs.append(e)
    if not errs:
        return None, None, 0
    m = float(np.mean(errs))
    return 1.0 / max(m * 100.0, 1e-6), m, len(errs)


def feature_purity(a):
    """(purity, number of clusters)."""
    ok = np.isfinite(a["x"]) & np.isin(a["label"], (2, 3))
    p, lab = _xyz(a)[ok], a["label"][ok]
    cl = _radius_components(p, DBSCAN_EPS, DBSCAN_MIN)
    ents = []
    for c in np.unique(cl[cl >= 0]):
        share = np.mean(lab[cl == c] == 2)
        ents.append(0.0 if share in (0.0, 1.0) else -(share * np.log2(share) + (1 - share) * np.log2(1 - share)))
    if not ents:
        return None, 0
    return 1.0 - float(np.mean(ents)), len(ents)


def _normals(p, tree, k=10):
    _, nn = tree.query(p, k)
    q = p[nn] - p[nn].mean(axis=1, keepdims=True)
    cov = np.einsum("nki,nkj->nij", q, q)
    _, v = np.linalg.eigh(cov)
    return v[:, :, 0]


def icp(src, dst, iters=30, max_dist=(2.0, 1.0, 0.5, 0.3)):
    """Point-to-plane ICP: 4x4 transform taking src onto dst."""
    tree = cKDTree(dst)
    nd = _normals(dst, tree)
    T = np.eye(4)
    s = src[:: max(1, len(src) // 20000)]
    for it in range(iters):
        cur = s @ T[:3, :3].T + T[:3, 3]
        d, j = tree.query(cur)
        m = d < max_dist[min(it * len(max_dist) // iters, len(max_dist) - 1)]
        if m.sum() < 6:
            break
        p, q, n = cur[m], dst[j[m]], nd[j[m]]
        A = np.hstack([np.cross(p, n), n])
        b = np.sum((q - p) * n, axis=1)
        x = np.linalg.lstsq(A, b, rcond=None)[0]
        rx, ry, rz = x[:3]
        R = np.array([[1, -rz, ry], [rz, 1, -rx], [-ry, rx, 1]])
        u, _, vt = np.linalg.svd(R)
        R = u @ vt
        dT = np.eye(4)
        dT[:3, :3], dT[:3, 3] = R, x[3:]
        T = dT @ T
        if np.linalg.norm(x) < 1e-6:
            break
    return T


def temporal_stability(a, b):
    """(stability, matched share, transform): a, b successive labelled frames."""
    pa = _xyz(a)
    pb = _xyz(b)
    oka = np.isfinite(pa).all(axis=1) & (a["label"] > 0)
    okb = np.isfinite(pb).all(axis=1) & (b["label"] > 0)
    pa, la, pb, lb = pa[oka], a["label"][oka], pb[okb], b["label"][okb]
    if len(pa) < 10 or len(pb) < 10:
        return None, 0.0, np.eye(4)
    T = icp(pb, pa)
    d, j = cKDTree(pa).query(pb @ T[:3, :3].T + T[:3, 3])
    m = d < MATCH_DIST
    if not m.any():
        return None, 0.0, T
    return float(np.mean(lb[m] == la[j[m]])), float(np.mean(m)), T
