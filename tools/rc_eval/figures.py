"""Figure 4 (convergence of the curvature) and Figure 7 (per-frame runtime by stage) of the paper,
from the package's own tools: convergence_table and process_bag --times-csv."""
import csv
import io
import subprocess

import numpy as np

from .runner import tool_command

STAGES = ("grid_ms", "features_ms", "thresholds_ms", "classification_ms", "primitives_ms", "core_output_ms")
STAGE_COLOURS = ("#bbbbbb", "#f2c200", "#8fbc5a", "#3182bd", "#d62728", "#9467bd")
# Section 5.4 of the paper: one VLP-16 frame, single thread, i7-12700 (features, quantiles,
# classification, components; total).
PAPER_MS = {"features_ms": 7.4, "thresholds_ms": 0.5, "classification_ms": 1.2, "primitives_ms": 3.3, "total": 12.4}


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def convergence_rows():
    """Rows of convergence_table's CSV (strings as printed), or raises RuntimeError."""
    cmd = tool_command("convergence_table")
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if res.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), res.returncode, res.stderr.strip()[-500:]))
    return list(csv.DictReader(io.StringIO(res.stdout))), res.stdout


def plot_convergence(rows, path):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    curves = {}
    for r in rows:
        curves.setdefault((r["shape"], r["formula"]), []).append((float(r["dtheta_rad"]), float(r["max_error"])))
    # distinct markers and sizes: the cylinder's and the ground's errors nearly coincide
    for i, ((shape, formula), pts) in enumerate(curves.items()):
        h, e = np.array(pts).T
        ax.loglog(h, e, ("-" if formula == "developed" else "--"), marker="o^sDv"[i % 5], ms=9 - 2 * (i % 3),
                  label="%s (%s)" % (shape, formula))
    h = np.array(sorted({float(r["dtheta_rad"]) for r in rows}))
    e0 = min(float(r["max_error"]) for r in rows if float(r["dtheta_rad"]) == h[-1])
    ax.loglog(h, e0 * h / h[-1], ":", color="0.4", label="slope 1 (first order)")
    ax.set_xlabel("azimuth step dtheta [rad]")
    ax.set_ylabel("max |kappa - kappa_exact| [1/m]")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def read_times(path):
    """{column: np.array} of a process_bag --times-csv file."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else {}


def plot_runtime_frames(times, path):
    """One panel per bag: the core's time per frame, stacked by stage (the paper's Figure 7)."""
    plt = _plt()
    bags = [b for b in times if times[b]]
    fig, axes = plt.subplots(1, len(bags), figsize=(3.2 * len(bags), 3.4), squeeze=False)
    for ax, b in zip(axes[0], bags):
        t = times[b]
        x = np.arange(1, len(t["core_ms"]) + 1)
        bottom = np.zeros(len(x))
        for s, c in zip(STAGES, STAGE_COLOURS):
            ax.bar(x, t[s], bottom=bottom, color=c, label=s[:-3])
            bottom += t[s]
        ax.set_title("%s\n%.0f points/frame" % (b, np.mean(t["points"])), fontsize=7)
        ax.set_xlabel("frame")
        ax.set_xticks(x)
    axes[0][0].set_ylabel("core ms / frame")
    axes[0][-1].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
