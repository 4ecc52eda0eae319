"""Labels on real scans against human annotations (issue 29): KITTI sequence 00 frames with their
SemanticKITTI classes (`<bag>_sem.npy`, one class per point, aligned 1:1 with the bag's
cloud), scored for the defaults, the paper as written and PCL PCA-Curv (k = 10) side by side.

Labels come from the package's own executables (runner.py: process_bag, baseline_labels), whose
labelled cloud keeps the input's points in the input's order, so point i of the output is point i
of the annotation.

Rows (issue 29; semantic classes as in the data's README):
  ground -> Plane     Plane share of the ground points (road 40, parking 44, sidewalk 48,
                      other-ground 49, lane-marking 60)
  building -> Plane   Plane share of the building points (50)
  vegetation -> Rough Rough share of the vegetation points (70)
  Plane purity        share of the Plane points whose class is not vegetation, trunk, pole or
                      traffic sign (70, 71, 80, 81)
  Rough purity        share of the Rough points whose class is neither ground nor building
  poles hit           share of the pole/trunk/sign objects with >= 1 Edge or Corner point: 3-D
                      clusters of the points of classes 71, 80, 81 (single linkage at 0.5 m, at
                      least 8 points; the clusters come from the annotation and the coordinates
                      alone, so they are the same for every labeller)
  Edge/Corner on veg. share of the Edge + Corner points whose class is vegetation (lower is better)

Denominators: only points the labeller labelled (label != 0) count. A point it left unlabelled
(out of range, an invalid return, a ring too short) is neither right nor wrong, so the "class ->
label" rows divide by the labelled points of the class, and the purity rows divide by the points
that carry the label in question (which are labelled by definition). The annotation's own
unlabelled (0) and outlier (1) points are kept: they count as "not vegetation/..." in the purity
rows, as the issue's definitions read. A pole cluster counts whether or not its points were
labelled (an unlabelled pole is a missed pole). "all frames" pools the counts of every frame
(numerators and denominators summed), it does not average the per-frame ratios.

  rosrun ring_curvature evaluate_real [--data DIR] [--json FILE]
"""
import argparse
import glob
import json
import os
import tempfile
import time

import numpy as np

from .cloud_io import read_bag_clouds
from .configs import BASELINES, PAPER
from .progress import Progress
from .runner import labelled_frames, run_method

TOPIC = "/velodyne_points"
PLANE, EDGE, CORNER, ROUGH = 1, 2, 3, 4

GROUND = (40, 44, 48, 49, 60)
BUILDING = (50,)
VEGETATION = (70,)
THIN = (71, 80, 81)  # trunk, pole, traffic sign
NOT_IN_PLANE = VEGETATION + THIN
NOT_IN_ROUGH = GROUND + BUILDING
CLUSTER_LINK = 0.5  # [m] single linkage of the thin-object clusters
CLUSTER_MIN = 8  # points

# (key, what the row measures, target, True when higher is better), issue 29's order and targets
ROWS = [
    ("ground_plane", "road/parking/sidewalk/lane-marking/other-ground -> Plane", 0.97, True),
    ("building_plane", "building -> Plane", 0.90, True),
    ("vegetation_rough", "vegetation -> Rough", 0.60, True),
    ("plane_purity", "Plane points that are not vegetation/trunk/pole/sign", 0.95, True),
    ("rough_purity", "Rough points that are not ground/building", 0.95, True),
    ("thin_hit", "poles/trunks/signs (3-D clusters of >= 8 points, 0.5 m linkage) with >= 1 Edge/Corner point",
     0.95, True),
    ("feature_on_vegetation", "Edge/Corner points that lie on vegetation (lower is better)", 0.15, False),
]
ROW_KEYS = [r[0] for r in ROWS]

# name -> (runner method, params): process_bag's defaults (an empty parameter file), the paper as
# written (configs.PAPER: Eq 9-11 and Algorithm 1's quartiles; non_max_suppression acts only in
# the robust classifier, so it needs no setting here), PCL PCA-Curv via baseline_labels.
LABELLERS = {"defaults": ("ours", {}), "paper": ("ours", PAPER), "pca": (BASELINES["PCA-Curv"], None)}


def default_data_dir():
    """RC_SHARED/data/real/labelled, else ../shared beside the repository (as scripts/common.sh)."""
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", ".."))
    shared = os.environ.get("RC_SHARED") or os.path.join(root, "..", "shared")
    return os.path.normpath(os.path.join(shared, "data", "real", "labelled"))


def labelled_bags(data_dir):
    """Bags in data_dir that have a `<bag>_sem.npy` beside them, sorted by name."""
    if not os.path.isdir(data_dir):
        return []
    return [b for b in sorted(glob.glob(os.path.join(data_dir, "*.bag")))
            if os.path.exists(os.path.splitext(b)[0] + "_sem.npy")]


def thin_clusters(xyz, sem):
    """[index arrays] of the clusters of trunk/pole/sign points: single linkage at CLUSTER_LINK,
    at least CLUSTER_MIN points."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree
    idx = np.flatnonzero(np.isin(sem, THIN) & np.all(np.isfinite(xyz), axis=1))
    if len(idx) == 0:
        return []
    pairs = cKDTree(xyz[idx]).query_pairs(CLUSTER_LINK, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(idx), len(idx)))
    n, comp = connected_components(graph, directed=False)
    sizes = np.bincount(comp, minlength=n)
    return [idx[comp == c] for c in np.flatnonzero(sizes >= CLUSTER_MIN)]


def frame_counts(label, sem, clusters):
    """{row: [numerator, denominator]} of one frame (see the module's docstring)."""
    label = np.asarray(label)
    on = label != 0
    feature = (label == EDGE) | (label == CORNER)

    def share(sel, good):
        return [int(np.count_nonzero(sel & good)), int(np.count_nonzero(sel))]

    return {
        "ground_plane": share(on & np.isin(sem, GROUND), label == PLANE),
        "building_plane": share(on & np.isin(sem, BUILDING), label == PLANE),
        "vegetation_rough": share(on & np.isin(sem, VEGETATION), label == ROUGH),
        "plane_purity": share(label == PLANE, ~np.isin(sem, NOT_IN_PLANE)),
        "rough_purity": share(label == ROUGH, ~np.isin(sem, NOT_IN_ROUGH)),
        "thin_hit": [sum(int(np.any(feature[c])) for c in clusters), len(clusters)],
        "feature_on_vegetation": share(feature, np.isin(sem, VEGETATION)),
    }


def ratio(nd):
    return None if nd[1] == 0 else nd[0] / nd[1]


def pool(counts):
    """Counts summed over frames."""
    out = {k: [0, 0] for k in ROW_KEYS}
    for c in counts:
        for k in ROW_KEYS:
            out[k][0] += c[k][0]
            out[k][1] += c[k][1]
    return out


def meets(key, value):
    target, higher = {r[0]: (r[2], r[3]) for r in ROWS}[key]
    if value is None:
        return False
    return value >= target if higher else value <= target


def ahead(key, a, b):
    """a strictly better than b on this row."""
    if a is None or b is None:
        return False
    higher = {r[0]: r[3] for r in ROWS}[key]
    return a > b if higher else a < b


def load_frames(bag, topic):
    """[(name, xyz, sem)] of a bag, one per cloud; the annotation is split over the bag's clouds
    in order (the shared bags hold one cloud each)."""
    # (a SemanticKITTI .label as it comes holds the instance in the upper 16 bits: the class is below)
    sem = np.load(os.path.splitext(bag)[0] + "_sem.npy").astype(np.uint32) & 0xFFFF
    clouds = read_bag_clouds(bag, topic)
    if sum(len(a) for _, a, _ in clouds) != len(sem):
        raise RuntimeError("%s: %d annotated points for %d cloud points" % (
            os.path.basename(bag), len(sem), sum(len(a) for _, a, _ in clouds)))
    out, start = [], 0
    stem = os.path.splitext(os.path.basename(bag))[0]
    for i, (_, a, _) in enumerate(clouds):
        xyz = np.stack([a["x"], a["y"], a["z"]], axis=1).astype(np.float64)
        name = stem if len(clouds) == 1 else "%s#%d" % (stem, i)
        out.append((name, xyz, sem[start:start + len(a)]))
        start += len(a)
    return out


def evaluate(bags, labellers=tuple(LABELLERS), topic=TOPIC, progress=None, sensor_params=None):
    """{"frames": [names], "labellers": {name: {"counts": {frame: counts}, "all": counts,
    "seconds": tool wall time} or {"error": text}}}. Every labeller labels the same frames."""
    frames, per_bag = [], []
    for b in bags:
        fr = load_frames(b, topic)
        per_bag.append(fr)
        frames += [f[0] for f in fr]
    clusters = {name: thin_clusters(xyz, sem) for fr in per_bag for name, xyz, sem in fr}
    out = {"frames": frames, "labellers": {}}
    with tempfile.TemporaryDirectory() as work:
        for lab in labellers:
            method, params = LABELLERS[lab]
            if method == "ours" and sensor_params:  # (what describes the sensor holds for both modes)
                params = dict(params, **sensor_params)
            counts, seconds = {}, 0.0
            try:
                for i, (b, fr) in enumerate(zip(bags, per_bag)):
                    lbag = os.path.join(work, "%s_%d.bag" % (lab, i))
                    seconds += run_method(method, b, lbag, params, topic)
                    got = labelled_frames(lbag)
                    os.unlink(lbag)
                    if len(got) != len(fr):
                        raise RuntimeError("%s: %d labelled clouds for %d input clouds" % (
                            os.path.basename(b), len(got), len(fr)))
                    for (name, xyz, sem), a in zip(fr, got):
                        if len(a) != len(sem) or not np.array_equal(  # (an organized cloud's no-returns: NaN)
                                np.stack([a["x"], a["y"], a["z"]], axis=1).astype(np.float64), xyz, equal_nan=True):
                            raise RuntimeError("%s: the labelled cloud is not the input's points in the "
                                               "input's order" % name)
                        counts[name] = frame_counts(a["label"], sem, clusters[name])
                    if progress:
                        progress.step("%s %s" % (lab, os.path.basename(b)))
            except (RuntimeError, OSError) as e:
                err = str(e).split("): ", 1)[-1].replace("\n", " ")[:200]
                if method != "ours":
                    err += " (baseline_labels is the lab's: RC_LAB=1 scripts/build)"
                out["labellers"][lab] = {"error": err}
                continue
            out["labellers"][lab] = {"counts": counts, "all": pool(counts.values()), "seconds": seconds}
    return out


def values(res, lab, frame=None):
    """{row: value or None} of a labeller on one frame (None: all frames pooled)."""
    r = res["labellers"].get(lab, {})
    if "counts" not in r:
        return {k: None for k in ROW_KEYS}
    c = r["all"] if frame is None else r["counts"][frame]
    return {k: ratio(c[k]) for k in ROW_KEYS}


def ahead_everywhere(res):
    """{row: defaults strictly better than pca on every frame and pooled} (None without both)."""
    labs = res["labellers"]
    if "counts" not in labs.get("defaults", {}) or "counts" not in labs.get("pca", {}):
        return None
    out = {}
    for k in ROW_KEYS:
        out[k] = all(ahead(k, values(res, "defaults", f)[k], values(res, "pca", f)[k])
                     for f in res["frames"] + [None])
    return out


def table(res, frame=None):
    """Markdown table of one frame (None: all frames pooled)."""
    labs = list(res["labellers"])
    vals = {lab: values(res, lab, frame) for lab in labs}
    cmp = "defaults" in labs and "pca" in labs and all(
        "counts" in res["labellers"][x] for x in ("defaults", "pca"))
    head = "| expectation (annotation -> label) | target | " + " | ".join(labs) + " |"
    head += " defaults ahead of pca |" if cmp else ""
    lines = [head, "|" + "---|" * (2 + len(labs) + (1 if cmp else 0))]
    for key, what, target, higher in ROWS:
        cells = []
        for lab in labs:
            v = vals[lab][key]
            if "error" in res["labellers"][lab]:
                cells.append("n/a")
            else:
                cells.append("-" if v is None else "%.3f %s" % (v, "ok" if meets(key, v) else "**miss**"))
        row = "| %s | %s %.2f | %s |" % (what, ">=" if higher else "<=", target, " | ".join(cells))
        if cmp:
            row += " %s |" % ("yes" if ahead(key, vals["defaults"][key], vals["pca"][key]) else "**no**")
        lines.append(row)
    return "\n".join(lines)


def markdown(res):
    L = ["# Labels against human annotations (SemanticKITTI)", "",
         "Frames: %s. Cells: share (ok / **miss** against issue 29's target); denominators are the "
         "points each labeller labelled (label != 0). Labellers: defaults = process_bag with the core's "
         "defaults; paper = the paper as written (%s); pca = PCL PCA-Curv, k = 10 (baseline_labels)." % (
             ", ".join(res["frames"]), ", ".join("%s %s" % kv for kv in PAPER.items())), ""]
    for lab, r in res["labellers"].items():
        if "error" in r:
            L += ["%s: not run: %s" % (lab, r["error"]), ""]
    L += ["## All %d frames pooled" % len(res["frames"]), "", table(res), ""]
    for f in res["frames"]:
        L += ["## %s" % f, "", table(res, f), ""]
    ev = ahead_everywhere(res)
    if ev is not None:
        behind = [k for k in ROW_KEYS if not ev[k]]
        L.append("Defaults ahead of PCA-Curv on every row and every frame: %s" % (
            "yes" if not behind else "no (not on: %s)" % ", ".join(behind)))
    for lab in res["labellers"]:
        v = values(res, lab)
        if "counts" in res["labellers"][lab]:
            missed = [k for k in ROW_KEYS if not meets(k, v[k])]
            L.append("%s meets every target (all frames pooled): %s" % (
                lab, "yes" if not missed else "no (%d of %d missed: %s)" % (len(missed), len(ROWS), ", ".join(missed))))
    return "\n".join(L) + "\n"


def as_json(res):
    ev = ahead_everywhere(res)
    out = {"rows": [{"key": k, "expectation": w, "target": t, "higher_is_better": h} for k, w, t, h in ROWS],
           "frames": res["frames"], "labellers": {}, "defaults_ahead_of_pca": ev}
    for lab, r in res["labellers"].items():
        if "error" in r:
            out["labellers"][lab] = {"error": r["error"]}
            continue
        pooled = values(res, lab)
        out["labellers"][lab] = {
            "all": pooled, "meets_target": {k: meets(k, pooled[k]) for k in ROW_KEYS},
            "per_frame": {f: values(res, lab, f) for f in res["frames"]},
            "counts": {"all": r["all"], "per_frame": r["counts"]}, "tool_seconds": r["seconds"]}
    return out


def parse(argv):
    p = argparse.ArgumentParser(prog="evaluate_real", description=__doc__.split("\n\n")[0])
    p.add_argument("--data", help="folder of labelled bags with <bag>_sem.npy beside them "
                                  "(default: $RC_SHARED/data/real/labelled, else ../shared beside the repository)")
    p.add_argument("--json", help="also write the numbers (and counts) as JSON to this file")
    p.add_argument("--labellers", nargs="+", choices=list(LABELLERS), default=list(LABELLERS))
    p.add_argument("--topic", default=TOPIC)
    p.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="a key of config/ring_curvature.yaml for ours' labellers (defaults, paper), "
                        "e.g. ring_field=ring_index for another sensor's layout (repeatable)")
    a = p.parse_args(argv)
    bad = [kv for kv in a.param if "=" not in kv]
    if bad:
        p.error("--param takes KEY=VALUE, not %s" % ", ".join(bad))
    a.param = dict(kv.split("=", 1) for kv in a.param)
    return a


def main(argv):
    a = parse(argv)
    data = a.data or default_data_dir()
    bags = labelled_bags(data)
    if not bags:
        print("evaluate_real: skipping: no labelled bags (<bag>.bag with <bag>_sem.npy) in %s "
              "(the shared real frames exist only on the team's machines)" % data)
        return 0
    t0 = time.monotonic()
    res = evaluate(bags, a.labellers, a.topic, Progress(len(bags) * len(a.labellers), "evaluate_real"), a.param)
    print(markdown(res), end="")
    print("\n(%d frame(s), %.0f s)" % (len(res["frames"]), time.monotonic() - t0))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(as_json(res), f, indent=1)
    return 0 if all("counts" in r for r in res["labellers"].values()) else 1
