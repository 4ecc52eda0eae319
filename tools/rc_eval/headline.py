"""The headline accuracy table: F1 per class and noise level for the defaults, the paper as
written, the ablations and the baselines, from accuracy_sweep's accuracy_modes.json."""
from .accuracy import f1

ROWS = ("default", "paper-as-written", "Ours-NoSmooth", "Ours-NoCurv", "PCA-Curv", "EuclideanClust")
SHOWN = ("Plane", "Edge", "Corner", "Rough")


def f1_of(summary, cls):
    """F1 of one class; None when the class is absent from the ground truth and the labels."""
    p, r = summary.get(cls, (None, None))
    if p is None and r is None:
        return None
    return f1(p, r)


def headline_table(sweep):
    """Markdown: one row per configuration in ROWS that the sweep ran, F1 per class at each noise
    level, then the mean F1 over the four classes (the sweep's ranking key)."""
    noises = sweep["noise"]
    res = sweep["results"]
    head = "| config | " + " | ".join("%s %g cm" % (c, 100 * n) for n in noises for c in SHOWN) + \
        " | " + " | ".join("mean %g cm" % (100 * n) for n in noises) + " |"
    lines = [head, "|" + "---|" * (1 + len(noises) * (len(SHOWN) + 1))]
    for name in ROWS:
        if name not in res:
            continue
        cells = []
        for n in noises:
            s = res[name][str(n)]["summary"]
            cells += ["-" if f1_of(s, c) is None else "%.2f" % f1_of(s, c) for c in SHOWN]
        cells += ["%.3f" % res[name][str(n)]["mean_f1"] for n in noises]
        lines.append("| %s | %s |" % (name, " | ".join(cells)))
    return "\n".join(lines)
