"""Ground truth and evaluation tools of ring_curvature (scene simulator, scorer, metrics)."""
