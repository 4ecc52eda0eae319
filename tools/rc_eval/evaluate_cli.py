"""Command line of tools/evaluate: the paper's metrics, ablations, baselines and (with ground
truth) accuracy on bags, the convergence study and per-frame runtime, written as a Markdown
report with PNG figures (report.py)."""
import argparse
import json
import os
import re
import subprocess
import tempfile

import numpy as np

from .accuracy import score_bag, summary
from .configs import ABLATIONS, BASELINES, PAPER
from .figures import convergence_rows, read_times
from .metrics import feature_purity, planarity, temporal_stability
from .progress import Progress
from .report import write_report
from .runner import labelled_frames, run_method, tool_command

METHODS = [("Ours-Full", "ours", {}), ("Ours-Paper", "ours", PAPER)] + \
    [(k, "ours", v) for k, v in ABLATIONS.items()] + [(k, v, None) for k, v in BASELINES.items()]


def parse(argv):
    p = argparse.ArgumentParser(prog="evaluate")
    p.add_argument("--bag", action="append", required=True, help="input bag (repeatable)")
    p.add_argument("--ground-truth", action="append", default=[],
                   help="simulator JSON sidecar of a --bag (its clouds carry the `gt` field)")
    p.add_argument("--report", required=True, help="output directory (report.md + PNGs)")
    p.add_argument("--topic", default="/velodyne_points")
    p.add_argument("--max-frames-stability", type=int, default=3, help="frame pairs per bag")
    p.add_argument("--no-benchmark", action="store_true", help="skip the timing runs")
    p.add_argument("--accuracy-json", help="accuracy_sweep's accuracy_modes.json: adds the headline F1 table")
    p.add_argument("--notes", help="Markdown inserted after the header (reproduce commands, differences)")
    return p.parse_args(argv)


def mean_std(v):
    v = [x for x in v if x is not None]
    return (float(np.mean(v)), float(np.std(v)), len(v)) if v else (None, None, 0)


def evaluate_bag(bag, topic, work, max_pairs, prog):
    """{method: metrics}, and the per-frame stage times of Ours-Full ({} when none)."""
    out, times = {}, {}
    for name, method, params in METHODS:
        lab = os.path.join(work, "labelled.bag")
        tcsv = os.path.join(work, "times.csv") if name == "Ours-Full" else None
        try:
            seconds = run_method(method, bag, lab, params, topic, times_csv=tcsv)
        except RuntimeError as e:
            out[name] = {"error": str(e).split("): ", 1)[-1].replace("\n", " ")[:160]}
            prog.step(name)
            continue
        if tcsv:
            times = {k: v.tolist() for k, v in read_times(tcsv).items()}
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
    return out, times


def benchmark(bag, topic):
    """Median ms/frame of ours and of the PCL baselines, from the package's benchmark tool."""
    args = ["--bag", bag, "--repeat", "5", "--baselines", "--baseline-repeat", "1", "--topic", topic]
    res = subprocess.run(tool_command("benchmark") + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if res.returncode != 0 or not res.stdout.strip():
        return None
    last = res.stdout.strip().splitlines()[-1]
    kv = dict(re.findall(r"(\w+)=([0-9.eE+-]+)", last))
    return {"pipeline_ms": float(kv.get("pipeline_ms", "nan")), "pca_curv_ms": float(kv.get("pca_curv_ms", "nan")),
            "euclid_ms": float(kv.get("euclid_ms", "nan")), "points": float(kv.get("points", "nan")),
            "command": " ".join(["rosrun", "ring_curvature", "benchmark"] + args)}  # (not this machine's path)


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
    prog = Progress(1 + len(bags) * (len(METHODS) + (0 if a.no_benchmark else 1)), "evaluate")
    results, bench, times = {}, {}, {}
    try:
        conv = convergence_rows()
    except RuntimeError as e:
        conv = (None, str(e))
    prog.step("convergence")
    with tempfile.TemporaryDirectory() as work:
        for b in bags:
            key = os.path.basename(b)
            results[key], times[key] = evaluate_bag(b, a.topic, work, a.max_frames_stability, prog)
            if not a.no_benchmark:
                bench[key] = benchmark(b, a.topic)
                prog.step("benchmark")
    sweep = None
    if a.accuracy_json:
        with open(a.accuracy_json) as f:
            sweep = json.load(f)
    write_report(a, METHODS, results, bench, times, conv, sweep, gts)
    print("evaluate: %d bag(s), report in %s" % (len(bags), os.path.join(a.report, "report.md")))
    return 0
