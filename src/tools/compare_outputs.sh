#!/usr/bin/env bash
# Checks that two builds of the core give byte-identical outputs: runs `process_bag` of each on
# the shipped fixtures and the shared real frames (those present), with four parameter sets
# that together exercise every mode, and compares the output bags with cmp. Every speed change
# is checked this way (docs/performance.md).
# usage: compare_outputs.sh BEFORE_DIR AFTER_DIR [WORK_DIR]
#   *_DIR: a folder with process_bag and the libring_curvature_{core,ros}.so it should load
#   (copied out of a workspace's devel/lib: LD_LIBRARY_PATH takes precedence over RUNPATH).
#   AFTER_WRAPPER: a command the after side's process_bag runs under (e.g. "env NAME=VALUE").
#   COMPARE_BAGS: a space-separated list of bags instead of the default set.
#   RC_SHARED: where the shared real frames are (default: ../shared beside the repository).
# Exit status: 0 when every output is identical, 1 otherwise.
set -euo pipefail
source "$(dirname "$0")/../../scripts/common.sh"
rc_source_ws
before=$(realpath "$1") after=$(realpath "$2")
# Without WORK_DIR the outputs (~1 GB) go to a temporary folder that is removed at the end.
if [[ $# -ge 3 ]]; then
  work=$3
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
real="$SHARED_REAL"
bags=("$REPO_ROOT"/rosbag_fixtures/*.bag
  "$real/nebula_vlp16_dual_4scans.bag" "$real/rustlidar_hdl32e_scans.bag"
  "$real/kitti_hdl64_patchworkpp_6frames.bag"
  "$real/ouster/ouster_os1_128_lb_rng15_3frames_organized.bag"
  "$real/ouster/ouster_os1_32_legacy_1frame_unorganized.bag"
  "$real/ouster/ouster_os0_32_dual_1frame_organized.bag")
[[ -n "${COMPARE_BAGS:-}" ]] && read -r -a bags <<<"$COMPARE_BAGS"
# Parameter sets: defaults; every alternative mode; the paper's curvature with rings from elevation;
# the inter-ring steps' non-default branches.
cat > "$work/defaults.yaml" <<'EOF'
min_range: 0.3
EOF
cat > "$work/modes.yaml" <<'EOF'
curvature_mode: developed
discontinuity_mode: paper
smoothness_mode: variance
classifier_mode: quartile
rough_primitives: true
EOF
cat > "$work/paper.yaml" <<'EOF'
curvature_mode: paper
ring_from_elevation: true
non_max_suppression: false
EOF
cat > "$work/inter_ring.yaml" <<'EOF'
rough_window_rings: 2
edge_support_noise: 0.0
foliage_keep_silhouettes: false
thin_occluded: false
EOF
differ=0 same=0
for bag in "${bags[@]}"; do
  [[ -f "$bag" ]] || { echo "skipped (absent): $bag"; continue; }
  topic=$(python3 - "$bag" <<'EOF'
import rosbag, sys
with rosbag.Bag(sys.argv[1]) as b:
    print([t for t, i in b.get_type_and_topic_info().topics.items() if i.msg_type == 'sensor_msgs/PointCloud2'][0])
EOF
)
  for params in defaults modes paper inter_ring; do
    name="$(basename "$bag" .bag).$params"
    for side in before after; do
      dir=${!side}
      wrapper=()
      [[ $side == after && -n "${AFTER_WRAPPER:-}" ]] && read -r -a wrapper <<<"$AFTER_WRAPPER"
      LD_LIBRARY_PATH="$dir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "${wrapper[@]}" "$dir/process_bag" --input "$bag" \
        --output "$work/$name.$side.bag" --topic "$topic" --params "$work/$params.yaml" \
        > "$work/$name.$side.log" 2>&1 || echo "process_bag failed ($side): $name (log: $work/$name.$side.log)"
    done
    if cmp -s "$work/$name.before.bag" "$work/$name.after.bag"; then
      same=$((same + 1))
    else
      differ=$((differ + 1))
      echo "DIFFERENT: $name"
    fi
  done
done
echo "identical: $same, different: $differ${3:+ (outputs in $work)}"
[[ $differ -eq 0 ]]
