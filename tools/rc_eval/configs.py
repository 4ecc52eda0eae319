"""The parameter sets the evaluation compares: every classification mode and scale of the core
(keys as in include/ring_curvature/params.hpp), the paper's ablations and the baselines."""
import itertools

CURVATURE = [("paper", {"curvature_mode": "paper"}), ("developed", {"curvature_mode": "developed"})] + [
    ("chord%.2f" % c, {"curvature_mode": "chord", "chord_length": c}) for c in (0.05, 0.10, 0.15, 0.25, 0.40)]
SMOOTHNESS = [(s, {"smoothness_mode": s}) for s in ("variance", "detrended")]
DISCONTINUITY = [(d, {"discontinuity_mode": d}) for d in ("paper", "jump")]
CLASSIFIER = [(c, {"classifier_mode": c}) for c in ("quartile", "robust")]

# The paper's Algorithm 1 with its own features, as written.
PAPER = {"curvature_mode": "paper", "smoothness_mode": "variance", "discontinuity_mode": "paper",
         "classifier_mode": "quartile"}

# Ablations of Table 2: the default configuration with one feature switched off in the core's
# classifier (Params::use_smoothness / use_curvature), everything else unchanged.
ABLATIONS = {"Ours-NoSmooth": {"use_smoothness": False}, "Ours-NoCurv": {"use_curvature": False},
             # the ring-wise labels alone: every inter-ring step (Params, section 6.2) off
             "Ours-RingOnly": {"inter_ring_roughness": False, "edge_vertical_support": False,
                               "suppress_foliage_features": False, "occlusion_aware_jumps": False,
                               "thin_objects": False}}
# The defaults with one inter-ring step (Params, section 6.2) switched off: what each one brings.
OPTIONS = {"Ours-NoInterRingRough": {"inter_ring_roughness": False},
           "Ours-NoEdgeSupport": {"edge_vertical_support": False},
           "Ours-NoFoliageSuppression": {"suppress_foliage_features": False},
           "Ours-NoOcclusionJumps": {"occlusion_aware_jumps": False},
           "Ours-NoThinObjects": {"thin_objects": False}}
BASELINES = {"PCA-Curv": "pca", "EuclideanClust": "euclid"}


def mode_grid():
    """[(name, params)] over every combination of modes and chord scales."""
    out = []
    for parts in itertools.product(CURVATURE, SMOOTHNESS, DISCONTINUITY, CLASSIFIER):
        name = "/".join(p[0] for p in parts)
        params = {}
        for _, p in parts:
            params.update(p)
        out.append((name, params))
    return out
