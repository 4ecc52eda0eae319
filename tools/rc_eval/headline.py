"""The headline accuracy table: F1 per class and noise level for the defaults, the defaults with
one inter-ring step switched off, the paper as written, the ablations and the
baselines, from accuracy_sweep's accuracy_modes.json."""
from .accuracy import f1

ROWS = ("default", "Ours-NoInterRingRough", "Ours-NoEdgeSupport", "Ours-NoFoliageSuppression",
        "Ours-NoOcclusionJumps", "Ours-NoThinObjects", "Ours-RingOnly", "paper-as-written",
        "Ours-NoSmooth", "Ours-NoCurv", "PCA-Curv", "EuclideanClust")
SHOWN = ("Plane", "Edge", "Corner", "Rough")


def f1_of(summary, cls):
    """F1 of one class; None when the class is absent from the ground truth and the labels."""
    p, r = summary.get(cls, (None, None))
    if p is None and r is None:
        return None
    return f1(p, r)


def headline_table(sweep):
    """Markdown: one row per configuration in ROWS that the sweep ran, F1 per class at each noise
    level, the mean F1 over the four classes (the sweep's ranking key), then the recall of thin
    objects (poles, trunks, signs found by an Edge or Corner; "-" where the scorer has no Thin)."""
    noises = sweep["noise"]
    res = sweep["results"]
    head = "| config | " + " | ".join("%s %g cm" % (c, 100 * n) for n in noises for c in SHOWN) + \
        " | " + " | ".join("mean %g cm" % (100 * n) for n in noises) + \
        " | " + " | ".join("thin R %g cm" % (100 * n) for n in noises) + " |"
    lines = [head, "|" + "---|" * (1 + len(noises) * (len(SHOWN) + 2))]
    for name in ROWS:
        if name not in res:
            continue
        cells = []
        for n in noises:
            s = res[name][str(n)]["summary"]
            cells += ["-" if f1_of(s, c) is None else "%.2f" % f1_of(s, c) for c in SHOWN]
        cells += ["%.3f" % res[name][str(n)]["mean_f1"] for n in noises]
        thin = [res[name][str(n)]["summary"].get("Thin", (None, None))[1] for n in noises]
        cells += ["-" if t is None else "%.2f" % t for t in thin]
        lines.append("| %s | %s |" % (name, " | ".join(cells)))
    return "\n".join(lines)
