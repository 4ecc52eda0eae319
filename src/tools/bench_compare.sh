#!/usr/bin/env bash
# Side-by-side timing of two builds of the core on a shared, noisy machine: runs the "before"
# and "after" benchmark binaries alternately (ABAB...) so that both see the same load, and
# prints each run's last line, then the median of pipeline_ms per side.
# usage: bench_compare.sh BEFORE_DIR AFTER_DIR BAG [ROUNDS] [extra benchmark args]
#   *_DIR holds `benchmark` and the libring_curvature_core.so it should load (copied out of a
#   workspace's devel/lib: the binary's RUNPATH yields to LD_LIBRARY_PATH).
set -euo pipefail
before=$1 after=$2 bag=$3 rounds=${4:-5}
shift $(( $# < 4 ? $# : 4 ))
declare -A ms=([before]="" [after]="")
for ((i = 0; i < rounds; i++)); do
  for side in before after; do
    dir=${!side}
    line=$(LD_LIBRARY_PATH="$dir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$dir/benchmark" --bag "$bag" "$@" | tail -n 1)
    echo "$side: $line"
    ms[$side]+="$(sed -nE 's/.*pipeline_ms=([0-9.]+).*/\1/p' <<<"$line") "
  done
done
for side in before after; do
  printf '%s median pipeline_ms over %d runs: ' "$side" "$rounds"
  tr ' ' '\n' <<<"${ms[$side]}" | grep . | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'
done
