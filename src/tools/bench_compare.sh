#!/usr/bin/env bash
# Side-by-side timing of two builds of the core on a shared, noisy machine: runs the "before"
# and "after" benchmark binaries alternately (ABBA...) so that both see the same load, and
# prints each run's last line, then per side the median over the runs of each stage's median
# and of pipeline_ms.
# usage: bench_compare.sh BEFORE_DIR AFTER_DIR BAG [ROUNDS] [extra benchmark args]
#   *_DIR holds `benchmark` and the libring_curvature_core.so it should load (copied out of the
#   devel/lib of a workspace built with the lab, RC_LAB=1 scripts/build: the binary's RUNPATH
#   yields to LD_LIBRARY_PATH).
set -euo pipefail
before=$1 after=$2 bag=$3 rounds=${4:-5}
shift $(( $# < 4 ? $# : 4 ))
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT
# ABBA order: each side runs first in half of the rounds. Run back to back, the second of a
# pair can measure slower (an identical copy of one build: 1.95 -> 2.12 ms, 9 rounds), so a
# fixed order would bias every comparison against the "after" build.
for ((i = 0; i < rounds; i++)); do
  order="before after"
  (( i % 2 == 1 )) && order="after before"
  for side in $order; do
    dir=${!side}
    out=$(LD_LIBRARY_PATH="$dir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$dir/benchmark" --bag "$bag" "$@")
    echo "$side: $(tail -n 1 <<<"$out")"
    # "side stage median" for the stage table's rows, and the pipeline from the last line
    awk -v s="$side" '/^  (grid|features|thresholds|classification|primitives|output) /{print s, $1, $2}
      /^frames=/{for (k = 1; k <= NF; ++k) if ($k ~ /^pipeline_ms=/) {sub("pipeline_ms=", "", $k); print s, "pipeline", $k}}' \
      <<<"$out" >> "$runs"
  done
done
python3 - "$runs" "$rounds" <<'PY'
import collections, statistics, sys
v = collections.defaultdict(list)
for line in open(sys.argv[1]):
    side, stage, ms = line.split()
    v[(stage, side)].append(float(ms))
print("median over %s runs [ms]   before     after" % sys.argv[2])
for stage in ["grid", "features", "thresholds", "classification", "primitives", "output", "pipeline"]:
    if (stage, "before") in v:
        print("  %-22s %9.3f %9.3f" % (stage, statistics.median(v[(stage, "before")]), statistics.median(v[(stage, "after")])))
PY
