"""Writes tools/evaluate's report: report.md, results.json, convergence.csv and the PNG figures."""
import json
import os
import subprocess

import numpy as np

from .accuracy import CLASSES
from .figures import PAPER_MS, STAGES, plot_convergence, plot_runtime_frames
from .headline import headline_table

COLOURS = {"Ours-Full": "#f2c200", "Ours-Paper": "#8fbc5a", "Ours-NoSmooth": "#9ecae1",
           "Ours-NoCurv": "#3182bd", "Ours-RingOnly": "#bbbbbb", "PCA-Curv": "#f28e2b",
           "EuclideanClust": "#d62728"}


def machine():
    """CPU model and count from lscpu: timings mean little without them."""
    try:
        out = subprocess.run(["lscpu"], stdout=subprocess.PIPE, text=True).stdout
    except OSError:
        return "unknown (lscpu not found)"
    kv = dict(ln.split(":", 1) for ln in out.splitlines() if ":" in ln)
    kv = {k.strip(): v.strip() for k, v in kv.items()}
    hv = kv.get("Hypervisor vendor")
    return "%s, %s CPU(s)%s" % (kv.get("Model name", "?"), kv.get("CPU(s)", "?"), ", %s guest" % hv if hv else "")


def fmt(m, digits=2):
    if m is None or m[0] is None:
        return "n/a"
    return "%.*f ± %.*f (n=%d)" % (digits, m[0], digits, m[1], m[2])


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_metrics(methods, results, path):
    """Bar charts like the paper's Figure 6: one row per bag, one column per metric."""
    plt = _plt()
    metrics = [("planarity", "Planarity score [1/cm]"), ("purity", "Feature purity"),
               ("stability", "Temporal stability")]
    fig, axes = plt.subplots(len(results), 3, figsize=(12, 3.0 * len(results)), squeeze=False)
    for row, (bag, res) in enumerate(results.items()):
        names = [n for n, _, _ in methods if n in res and "error" not in res[n]]
        for col, (key, title) in enumerate(metrics):
            ax = axes[row][col]
            vals = [res[n][key][0] if res[n][key][0] is not None else 0 for n in names]
            errs = [res[n][key][1] if res[n][key][1] is not None else 0 for n in names]
            ax.bar(range(len(names)), vals, yerr=errs, color=[COLOURS[n] for n in names], capsize=3)
            ax.set_xticks(range(len(names)))
            ax.set_xticklabels(names, rotation=30, ha="right", fontsize=7)
            ax.set_title("%s\n%s" % (title, bag), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def convergence_section(conv, report_dir):
    rows, text = conv
    if rows is None:
        return ["## Convergence (Figure 4)", "", "Not measured: %s" % text, ""]
    with open(os.path.join(report_dir, "convergence.csv"), "w") as f:
        f.write(text)
    plot_convergence(rows, os.path.join(report_dir, "convergence.png"))
    L = ["## Convergence (Table 1, Figure 4)", "",
         "`rosrun ring_curvature convergence_table` (CSV in convergence.csv): max error of the discrete "
         "curvature over all samples of one analytic ring against the exact geodesic curvature of the "
         "continuous trace on the cone (test/support/cone_curves.hpp), float64 input, the same traces as "
         "test/core/test_convergence.cpp. EOC = log2(e(2h) / e(h)).", "", "![convergence](convergence.png)", "",
         "| shape | formula | dtheta | K | max error [1/m] | EOC |", "|---|---|---|---|---|---|"]
    for r in rows:
        L.append("| %s | %s | %s | %s | %.3e | %s |" % (r["shape"], r["formula"], r["dtheta"], r["K"],
                                                     float(r["max_error"]), r["eoc"] or "-"))
    return L + [""]


def runtime_section(times, gts, bench, report_dir):
    real = {b: t for b, t in times.items() if t and b not in gts}
    L = ["## Per-frame runtime (Figure 7)", "",
         "Core time per frame by stage, from `process_bag --times-csv` on the real frames (Ours-Full, one "
         "process, single thread, the ROS message building excluded). Paper, section 5.4, VLP-16 on an "
         "i7-12700: features %.1f, quantiles %.1f, classification %.1f, components %.1f, total %.1f ms." % (
             PAPER_MS["features_ms"], PAPER_MS["thresholds_ms"], PAPER_MS["classification_ms"],
             PAPER_MS["primitives_ms"], PAPER_MS["total"]), ""]
    if not real:
        return L + ["No real-frame timings (no bag without ground truth was given).", ""]
    plot_runtime_frames(real, os.path.join(report_dir, "runtime_frames.png"))
    L += ["![runtime per frame](runtime_frames.png)", "",
          "| bag | frames | points/frame | " + " | ".join(s[:-3] for s in STAGES) + " | core ms (mean) | core ms (max) |",
          "|---|---|---|" + "---|" * (len(STAGES) + 2)]
    for b, t in real.items():
        L.append("| %s | %d | %.0f | %s | %.2f | %.2f |" % (
            b, len(t["core_ms"]), np.mean(t["points"]), " | ".join("%.2f" % np.mean(t[s]) for s in STAGES),
            np.mean(t["core_ms"]), np.max(t["core_ms"])))
    if any(bench.values()):
        L += ["", "Baselines on the same bags, medians from `rosrun ring_curvature benchmark --bag BAG --repeat 5 "
              "--baselines --baseline-repeat 1` (single thread; paper: PCA-Curv 42.3 ms, Euclidean 79.5 ms):", "",
              "| bag | points/frame | Ours-Full ms | PCA-Curv ms | EuclideanClust ms |", "|---|---|---|---|---|"]
        for b, r in bench.items():
            if r:
                L.append("| %s | %.0f | %.2f | %.1f | %.1f |" % (b, r["points"], r["pipeline_ms"], r["pca_curv_ms"],
                                                               r["euclid_ms"]))
    return L + [""]


def bag_section(bag, res, methods, gts):
    L = ["## %s" % bag, "", "| method | Planarity score | Feature purity | Temporal stability | "
         "Plane / Edge / Corner / Rough share |", "|---|---|---|---|---|"]
    for name, _, _ in methods:
        r = res.get(name)
        if r is None:
            continue
        if "error" in r:
            L.append("| %s | n/a: %s | | | |" % (name, r["error"].replace("|", "/")))
            continue
        share = " / ".join("%.0f%%" % (100 * s) for s in r["label_share"][1:])
        L.append("| %s | %s | %s | %s | %s |" % (name, fmt(r["planarity"]), fmt(r["purity"]), fmt(r["stability"]),
                                                 share))
    acc = [(n, res[n]["accuracy"]) for n, _, _ in methods if n in res and "accuracy" in res[n]]
    if acc:
        L += ["", "Accuracy against the simulator's ground truth (precision / recall; rules in "
              "tools/rc_eval/scoring.py):", "", "| method | " + " | ".join(CLASSES) + " |",
              "|---|" + "---|" * len(CLASSES)]
        for n, s in acc:
            L.append("| %s | %s |" % (n, " | ".join(
                "%s / %s" % tuple("-" if v is None else "%.2f" % v for v in s[c]) for c in CLASSES)))
    if bag in gts:
        L += ["", "Scene: `%s` (simulator sidecar)." % gts[bag]]
    return L + [""]


def write_report(a, methods, results, bench, times, conv, sweep, gts):
    os.makedirs(a.report, exist_ok=True)
    plot_metrics(methods, results, os.path.join(a.report, "metrics.png"))
    cmd = "rosrun ring_curvature evaluate %s --report %s" % (
        " ".join("--bag %s" % b for b in a.bag) + "".join(" --ground-truth %s" % g for g in a.ground_truth), a.report)
    if a.accuracy_json:
        cmd += " --accuracy-json %s" % a.accuracy_json
    if a.notes:
        cmd += " --notes %s" % a.notes
    L = ["# ring_curvature evaluation", "", "Generated by `%s`." % cmd, "",
         "Machine: %s. All timings were taken on this shared 2-core virtual machine, with other jobs "
         "running; they are indicative, not a benchmark of the method." % machine(), ""]
    if a.notes:
        with open(a.notes) as f:
            L += [f.read().rstrip(), ""]
    if sweep:
        L += ["## Accuracy on simulated scenes: F1 per class", "",
              "From `%s` (%s, seeds %s; full precision / recall for every mode in accuracy_modes.md). "
              "default = the core's Params; paper-as-written = Eq 9/10/11 + Algorithm 1 literally; "
              "Ours-NoSmooth / Ours-NoCurv = default with use_smoothness / use_curvature false." % (
                  a.accuracy_json, sweep.get("sensor"), sweep.get("seeds")), "", headline_table(sweep), ""]
    L += convergence_section(conv, a.report)
    L += runtime_section(times, gts, bench, a.report)
    L += ["## The paper's metrics per bag (Table 2, Figure 6)", "",
          "Metrics as section 5.3.1 of the paper names them; the constants it leaves open are fixed in "
          "tools/rc_eval/metrics.py (Planarity = 1 / mean RANSAC plane error **in cm**; purity over DBSCAN "
          "eps 0.5 m clusters; stability after point-to-plane ICP, 0.2 m match radius). Mean ± standard "
          "deviation over frames (stability: over successive frame pairs).", "", "![metrics](metrics.png)", ""]
    for bag, res in results.items():
        L += bag_section(bag, res, methods, gts)
    with open(os.path.join(a.report, "report.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    with open(os.path.join(a.report, "results.json"), "w") as f:
        json.dump({"results": results, "benchmark": bench, "times": times}, f, indent=1)
