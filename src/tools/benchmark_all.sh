#!/usr/bin/env bash
# Runs the benchmark over the shipped fixtures and the shared real frames (skipping, with a note,
# any that are absent: a user's clone has no ../shared; RC_SHARED names another place), printing each run's full table.
# The figures in docs/performance.md come from this script:
#   src/tools/benchmark_all.sh [REPEAT [--params FILE.yaml]]   (uses $RC_WS or .catkin_ws; builds the benchmark,
#                                            a lab tool, with RC_LAB=1 if the workspace lacks it)
set -euo pipefail
source "$(dirname "$0")/../../scripts/common.sh"
rc_lab_tools benchmark
rc_source_ws
repeat=${1:-20}
shift || true  # the rest (e.g. --params FILE.yaml) goes to every benchmark run
real="$SHARED_REAL"
bags=(
  "$REPO_ROOT/rosbag_fixtures/rustlidar_velodyne_vlp16_vlp16_1scan.bag"
  "$REPO_ROOT/rosbag_fixtures/nebula_vlp16_lastreturn_4scans.bag"
  "$real/nebula_vlp16_dual_4scans.bag"
  "$real/rustlidar_hdl32e_scans.bag"
  "$real/kitti_hdl64_patchworkpp_6frames.bag"
  "$real/ouster/ouster_os1_128_lb_rng15_3frames_organized.bag"
)
for bag in "${bags[@]}"; do
  if [[ ! -f "$bag" ]]; then
    echo "skipped (absent): $bag"
    continue
  fi
  rosrun ring_curvature benchmark --bag "$bag" --repeat "$repeat" --baselines "$@"
  echo
done
