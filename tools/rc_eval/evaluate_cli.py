"""Command line of tools/evaluate: the paper's metrics, ablations, baselines and (with ground
truth) accuracy on bags, written as a Markdown report with PNG figures."""
import argparse
import json
import os
import re
import subprocess
import tempfile

import numpy as np

from .accuracy import CLASSES, score_bag, summary
from .configs import ABLATIONS, BASELINES, PAPER
from .metrics import feature_purity, planarity, temporal_stability
from .progress import Progress
from .runner import labelled_frames, run_method, tool_command

METHODS = [("Ours-Full", "ours", {}), ("Ours-Paper", "ours", PAPER)] + \
    [(k, "ours", v) for k, v in ABLATIONS.items()] + [(k, v, None) for k, v in BASELINES.items()]
COLOURS = {"Ours-Full": "#f2c200", "Ours-Paper": "#8fbc5a", "Ours-NoSmooth": "#9ecae1",
           "Ours-NoCurv": "#3182bd", "PCA-Curv": "#f28e2b", "EuclideanClust": "#d62728"}


def parse(argv):
    p = argparse.ArgumentParser(prog="evaluate")
    p.add_argument("--bag", action="append", required=True, help="input bag (repeatable)")
    p.add_argument("--ground-truth", action="append", default=[],
                   help="simulator JSON sidecar of a --bag (its clouds carry the `gt` field)")
    p.add_argument("--report", required=True, help="output directory (report.md + PNGs)")
    p.add_argument("--topic", default="/velodyne_points")
    p.add_argument("--max-frames-stability", type=int, default=3, help="frame pairs per bag")
    p.add_argument("--no-benchmark", action="store_true", help="skip the timing runs")
    return p.parse_args(argv)


def mean_std(v):
    v = [x for x in v if x is not None]
    return (float(np.mean(v)), float(np.std(v)), len(v)) if v else (None, None, 0)


def evaluate_bag(bag, topic, work, max_pairs, prog):
    out = {}
    for name, method, params in METHODS:
        lab = os.path.join(work, "labelled.bag")
        try:
            seconds = run_method(method, bag, lab, params, topic)
        except RuntimeError as e:
            out[name] = {"error": str(e).split("): ", 1)[-1].replace("\n", " ")[:160]}
            prog.step(name)
            continue
        frames = labelled_frames(lab)
        pl = [planarity(a)[0] for a in frames]
        pu = [feature_purity(a)[0] for a in frames]
        st = [temporal_stability(frames[i], frames[i + 1])[0] for i in range(min(len(frames) - 1, max_pairs))]
        r = {"frames": len(frames), "tool_seconds": seconds, "planarity": mean_std(pl),
             "purity": mean_std(pu), "stability": mean_std(st),
             "label_share": [float(np.mean(np.concatenate([a["label"] for a in frames]) == k)) for k in range(5)]}
        if frames and "gt" in frames[0].dtype.names:
            r["accuracy"] = summary(score_bag(lab))
        out[name] = r
        os.unlink(lab)
        prog.step(name)
    return out


def benchmark(bag, topic):
    """Median ms/frame of ours and of the PCL baselines, from the package's benchmark tool."""
    cmd = tool_command("benchmark") + ["--bag", bag, "--repeat", "5", "--baselines", "--baseline-repeat", "1",
                                      "--topic", topic]
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if res.returncode != 0 or not res.stdout.strip():
        return None
    last = res.stdout.strip().splitlines()[-1]
    kv = dict(re.findall(r"(\w+)=([0-9.eE+-]+)", last))
    head = [ln for ln in res.stdout.splitlines() if "cpu:" in ln]
    return {"pipeline_ms": float(kv.get("pipeline_ms", "nan")), "pca_curv_ms": float(kv.get("pca_curv_ms", "nan")),
            "euclid_ms": float(kv.get("euclid_ms", "nan")), "points": float(kv.get("points", "nan")),
            "cpu": head[0].split("cpu:")[1].strip() if head else "", "command": " ".join(cmd)}


def fmt(m, digits=2):
    if m is None or m[0] is None:
        return "n/a"
    return "%.*f ± %.*f (n=%d)" % (digits, m[0], digits, m[1], m[2])


def plot_metrics(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    metrics = [("planarity", "Planarity score [1/cm]"), ("purity", "Feature purity"),
               ("stability", "Temporal stability")]
    fig, axes = plt.subplots(len(results), 3, figsize=(12, 3.0 * len(results)), squeeze=False)
    for row, (bag, res) in enumerate(results.items()):
        names = [n for n, _, _ in METHODS if n in res and "error" not in res[n]]
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


def plot_runtime(bench, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bags = [b for b in bench if bench[b]]
    fig, ax = plt.subplots(figsize=(8, 3.5))
    w = 0.25
    for i, (key, name) in enumerate((("pipeline_ms", "Ours-Full"), ("pca_curv_ms", "PCA-Curv"),
                                     ("euclid_ms", "EuclideanClust"))):
        ax.bar(np.arange(len(bags)) + (i - 1) * w, [bench[b][key] for b in bags], w, label=name, color=COLOURS[name])
    ax.axhline(40.0, color="0.5", lw=1, label="40 ms (25 FPS)")
    ax.set_xticks(range(len(bags)))
    ax.set_xticklabels(bags, rotation=20, ha="right", fontsize=7)
    ax.set_ylabel("median ms / frame")
    ax.set_yscale("log")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_report(a, results, bench, gts):
    os.makedirs(a.report, exist_ok=True)
    plot_metrics(results, os.path.join(a.report, "metrics.png"))
    have_bench = any(bench.values())
    if have_bench:
        plot_runtime(bench, os.path.join(a.report, "runtime.png"))
    L = ["# ring_curvature evaluation", "",
         "Generated by `rosrun ring_curvature evaluate %s --report %s`." % (
             " ".join("--bag %s" % b for b in a.bag) + "".join(" --ground-truth %s" % g for g in a.ground_truth),
             a.report), "",
         "Metrics as section 5.3.1 of the paper names them; the constants it leaves open are fixed in "
         "tools/rc_eval/metrics.py (Planarity = 1 / mean RANSAC plane error **in cm**; purity over "
         "DBSCAN eps 0.5 m clusters; stability after point-to-plane ICP, 0.2 m match radius). "
         "Mean ± standard deviation over frames (stability: over successive frame pairs).", "",
         "![metrics](metrics.png)", ""]
    for bag, res in results.items():
        L += ["## %s" % bag, "", "| method | Planarity score | Feature purity | Temporal stability | "
              "Plane / Edge / Corner / Rough share |", "|---|---|---|---|---|"]
        for name, _, _ in METHODS:
            r = res.get(name)
            if r is None:
                continue
            if "error" in r:
                L.append("| %s | n/a: %s | | | |" % (name, r["error"].replace("|", "/")))
                continue
            share = " / ".join("%.0f%%" % (100 * s) for s in r["label_share"][1:])
            L.append("| %s | %s | %s | %s | %s |" % (name, fmt(r["planarity"]), fmt(r["purity"]),
                                                     fmt(r["stability"]), share))
        acc = [(n, res[n]["accuracy"]) for n, _, _ in METHODS if n in res and "accuracy" in res[n]]
        if acc:
            L += ["", "Accuracy against the simulator's ground truth (precision / recall; rules in "
                  "tools/rc_eval/scoring.py):", "",
                  "| method | " + " | ".join(CLASSES) + " |", "|---|" + "---|" * len(CLASSES)]
            for n, s in acc:
                L.append("| %s | %s |" % (n, " | ".join(
                    "%s / %s" % tuple("-" if v is None else "%.2f" % v for v in s[c]) for c in CLASSES)))
        if bag in gts:
            L += ["", "Scene: `%s` (simulator sidecar)." % gts[bag]]
        L.append("")
    if have_bench:
        L += ["## Runtime", "", "![runtime](runtime.png)", "",
              "| bag | points/frame | Ours-Full ms | PCA-Curv ms | EuclideanClust ms | CPU |", "|---|---|---|---|---|---|"]
        for b, r in bench.items():
            if r:
                L.append("| %s | %.0f | %.2f | %.1f | %.1f | %s |" % (b, r["points"], r["pipeline_ms"],
                                                                     r["pca_curv_ms"], r["euclid_ms"], r["cpu"]))
        L += ["", "Medians from `rosrun ring_curvature benchmark --bag BAG --repeat 5 --baselines "
              "--baseline-repeat 1` (single thread)."]
    elif not a.no_benchmark:
        L += ["## Runtime", "", "Not measured: the package's `benchmark` tool did not run (not built?)."]
    with open(os.path.join(a.report, "report.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    with open(os.path.join(a.report, "results.json"), "w") as f:
        json.dump({"results": results, "benchmark": bench}, f, indent=1)


def main(argv):
    a = parse(argv)
    missing = [b for b in a.bag if not os.path.exists(b)]
    for b in missing:
        print("evaluate: skipping %s: not found (the shared real frames exist only on the team's "
              "machines)" % b)
    bags = [b for b in a.bag if b not in missing]
    if not bags:
        print("evaluate: no input bag found; nothing to do")
        return 0
    gts = {os.path.basename(b): g for b, g in zip(a.bag, a.ground_truth) if b in bags}
    prog = Progress(len(bags) * (len(METHODS) + (0 if a.no_benchmark else 1)), "evaluate")
    results, bench = {}, {}
    with tempfile.TemporaryDirectory() as work:
        for b in bags:
            results[os.path.basename(b)] = evaluate_bag(b, a.topic, work, a.max_frames_stability, prog)
            if not a.no_benchmark:
                bench[os.path.basename(b)] = benchmark(b, a.topic)
                prog.step("benchmark")
    write_report(a, results, bench, gts)
    print("evaluate: %d bag(s), report in %s" % (len(bags), os.path.join(a.report, "report.md")))
    return 0
