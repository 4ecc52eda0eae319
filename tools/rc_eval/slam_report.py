"""tools/slam_benchmark's table: every row, ours over stock per sequence and on average (the
figures the targets are stated in), and the checks of a floor file (scripts/test.d/85-slam)."""
import json


COLS = [("sequence", "%-18s", "sequence"), ("frontend", "%-10s", "front end"), ("mapped", "%7s", "mapped"),
        ("ate_odom", "%8.3f", "ATE odo"), ("ate_map", "%8.3f", "ATE map"), ("ate_aligned_odom", "%8.3f", "ATEa odo"),
        ("ate_aligned_map", "%8.3f", "ATEa map"), ("drift_odom", "%9.2f", "drift%odo"),
        ("drift_map", "%9.2f", "drift%map"), ("n_sharp", "%6.0f", "sharp"), ("n_less_sharp", "%6.0f", "lsharp"),
        ("n_flat", "%6.0f", "flat"), ("n_less_flat", "%7.0f", "lflat"), ("fe_cpu_ms", "%7.1f", "fe ms"),
        ("fe_callback_ms", "%7.1f", "cb ms")]


def print_table(rows):
    head = "  ".join(("%" + f.lstrip("%").split(".")[0].rstrip("sfd") + "s") % h for _, f, h in COLS)
    print(head)
    for r in rows:
        cells = []
        for key, fmt, _ in COLS:
            v = r.get(key, float("nan"))
            if key == "mapped":
                v = "%d/%d" % (r.get("mapped", 0), r.get("frames", 0))
                cells.append("%7s" % v)
            else:
                cells.append(fmt % v)
        print("  ".join(cells) + ("   " + r["error"] if r.get("error") else ""))
    ratios(rows)
    print("ATE: position RMSE [m] after aligning the first pose; ATEa: after the rigid alignment that "
          "best fits the whole trajectory (TUM evaluate_ate / evo APE); drift: final position error / "
          "ground-truth path length [%];\nfeatures: mean points per frame on the four feature topics; "
          "fe ms: front-end CPU time per frame (all threads of ascanRegistration / of ours' "
          "nodelet manager, from /proc schedstat);\ncb ms: the front end's own "
          "per-frame callback time (ascanRegistration's printed TicToc, ours' ~frame_stats callback_ms).")


def frontend_key(name):
    """"ours" for every variant of our front end (ours, ours(stub)), else the name."""
    return "ours" if name.startswith("ours") else name


def ratios(rows):
    """Ours over stock per sequence and on average, for each ATE and the front-end time: the
    figures the targets are stated in."""
    by = {}
    for r in rows:
        by.setdefault(r["sequence"], {})[frontend_key(r["frontend"])] = r
    keys = [("ate_map", "ATE map"), ("ate_odom", "ATE odo"), ("ate_aligned_map", "ATEa map"),
            ("ate_aligned_odom", "ATEa odo"), ("fe_cpu_ms", "fe ms"), ("fe_callback_ms", "cb ms")]
    pairs = {s: b for s, b in by.items() if "ours" in b and "stock" in b}
    if not pairs:
        return
    print("\nours / stock       " + "  ".join("%9s" % h for _, h in keys))
    sums = [[] for _ in keys]
    for s in sorted(pairs):
        cells = []
        for j, (k, _) in enumerate(keys):
            o, st = pairs[s]["ours"].get(k, float("nan")), pairs[s]["stock"].get(k, float("nan"))
            v = o / st if st and st == st and o == o else float("nan")
            sums[j].append(v)
            cells.append("%9.2f" % v)
        print("%-18s " % s + "  ".join(cells))
    print("%-18s " % "mean" + "  ".join("%9.2f" % (sum(v) / len(v)) for v in sums))


def check_floor(rows, path):
    """Checks from the floor file; prints 'check ok|FAIL: ...' lines, returns the failures."""
    with open(path) as f:
        floor = json.load(f)
    fails = 0
    for seq, lim in floor.get("sequences", {}).items():
        by = {r["frontend"]: r for r in rows if r["sequence"] == seq}
        for fe, r in by.items():
            ok = r.get("failed", 1) == 0 and r.get("mapped", 0) == r.get("frames", -1) and r["frames"] > 0
            print("check %s: %s %s: every frame mapped (%d/%d)" % ("ok" if ok else "FAIL", seq, fe,
                                                                   r.get("mapped", 0), r.get("frames", 0)))
            fails += not ok
            key = frontend_key(fe)
            if key in lim.get("ate_map_max", {}):
                m = lim["ate_map_max"][key]
                ok = r.get("ate_map", float("inf")) <= m
                print("check %s: %s %s: mapped ATE %.3f m <= floor %.3f m" % ("ok" if ok else "FAIL", seq, fe,
                                                                               r.get("ate_map", float("nan")), m))
                fails += not ok
        ours = [r for f, r in by.items() if f.startswith("ours")]
        if ours and "stock" in by and "ours_over_stock_max" in lim:
            o, s = ours[0]["ate_map"], by["stock"]["ate_map"]
            m = lim["ours_over_stock_max"]
            ok = o <= s * m + lim.get("ours_over_stock_slack_m", 0.0)
            print("check %s: %s: %s mapped ATE %.3f m <= %.2f x stock's %.3f m + %.3f m" % (
                "ok" if ok else "FAIL", seq, ours[0]["frontend"], o, m, s, lim.get("ours_over_stock_slack_m", 0.0)))
            fails += not ok
    return fails
