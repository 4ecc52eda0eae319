#!/usr/bin/env bash
# The package as a user gets it from an install space, run by scripts/test.d/65-install in an
# environment that has sourced that install space and nothing of this repository's workspace:
#   run_installed.sh INSTALL_PREFIX OUT_DIR
# Prints one PASS/FAIL line per check.
set -uo pipefail
INSTALL=$1 OUT=$2
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/../.." && pwd)"
FIXTURE="$REPO/rosbag_fixtures/nebula_vlp16_lastreturn_4scans.bag"
export ROS_HOME="$OUT/ros_home" ROS_LOG_DIR="$OUT/logs/ros" PYTHONDONTWRITEBYTECODE=1
set +u; source "$INSTALL/setup.bash"; set -u
source "$REPO/scripts/ros_session.sh"
trap rs_stop_all EXIT

result() {  # result NAME STATUS(0 = pass)
  if [[ $2 -eq 0 ]]; then echo "PASS $1"; else echo "FAIL $1"; fi
}

# 1. ROS resolves the package, its plugin and its launch files in the install space.
[[ "$(rospack find ring_curvature)" == "$INSTALL/share/ring_curvature" ]]
result "rospack finds ring_curvature in the install space ($(rospack find ring_curvature 2>&1))" $?
plugin=$(rospack plugins --attrib=plugin nodelet | sed -n 's/^ring_curvature //p')
[[ "$plugin" == "$INSTALL/share/ring_curvature/nodelet_plugins.xml" && -f "$plugin" ]]
result "the nodelet plugin is registered from the install space" $?
# (vlp16.launch without its driver: Debian has no velodyne_pointcloud)
for launch in ring_curvature.launch aloam_frontend.launch "replay.launch bag:=$FIXTURE" "vlp16.launch driver:=false"; do
  roslaunch --nodes ring_curvature $launch > "$OUT/logs/nodes_${launch%% *}.txt" 2>&1
  result "roslaunch resolves the installed ${launch%% *}" $?
done

# 2. The offline tool, on a shipped bag.
rosrun ring_curvature process_bag --input "$FIXTURE" --output "$OUT/process_bag.bag" > "$OUT/logs/process_bag.log" 2>&1 &&
  python3 - "$OUT/process_bag.bag" <<'PY'
import sys, rosbag
with rosbag.Bag(sys.argv[1]) as b:
    msgs = [m for _, m, _ in b.read_messages(topics=["/ring_curvature/labelled_points"])]
assert len(msgs) == 4 and all("label" in [f.name for f in m.fields] and m.width * m.height > 10000 for m in msgs), len(msgs)
PY
result "installed process_bag labels the 4 frames of a shipped bag" $?

# The installed scene simulator (the evaluation's ground-truth scenes), through process_bag.
( cd "$OUT" && rosrun ring_curvature simulate_scene --sensor vlp16 --scene box --frames 1 \
    --output "$OUT/box.bag" --ground-truth "$OUT/box_gt.npy" > "$OUT/logs/simulate_scene.log" 2>&1 ) &&
  rosrun ring_curvature process_bag --input "$OUT/box.bag" --output "$OUT/box_labelled.bag" > "$OUT/logs/process_box.log" 2>&1 &&
  python3 - "$OUT/box_labelled.bag" <<'PY'
import sys, rosbag
with rosbag.Bag(sys.argv[1]) as b:
    assert b.get_message_count("/ring_curvature/labelled_points") == 1
PY
result "installed simulate_scene writes a scene that process_bag labels" $?

# 3. The nodelet in a nodelet manager, loaded by pluginlib from the install space, on a replay.
live() {
  rs_roscore "$(rs_free_port 11711)" "$OUT/logs" || return 1
  rs_start "$OUT/logs/nodelet.log" roslaunch --wait ring_curvature ring_curvature.launch || return 1
  local launch_pid=$RS_LAST_PID
  rs_start "$OUT/frame_stats.txt" rostopic echo -n 1 /ring_curvature/frame_stats
  local echo_pid=$RS_LAST_PID
  # the lazy nodelet subscribes to its input once an output has a subscriber
  rs_wait_subscribers /velodyne_points 1 60 "$launch_pid" "$echo_pid" || return 1
  rosbag play --quiet "$FIXTURE" > "$OUT/logs/play.log" 2>&1 || return 1
  for _ in $(seq 100); do kill -0 "$echo_pid" 2>/dev/null || break; sleep 0.2; done
  grep -qE '^points: [1-9][0-9]{3,}' "$OUT/frame_stats.txt"
}
live
st=$?
[[ $st -ne 0 ]] && tail -n 5 "$OUT"/logs/*.log "$OUT/frame_stats.txt" 2>/dev/null
result "installed nodelet in a manager labels a replayed frame (frame_stats: $(grep -m1 '^points:' "$OUT/frame_stats.txt" 2>/dev/null))" $st
rs_stop_all

# 4. A user's package built against the install space: headers, libraries and messages exported.
ws="$OUT/downstream_ws"
rm -rf "$ws" && mkdir -p "$ws/src" && cp -r "$HERE/downstream" "$ws/src/rc_downstream"
( cd "$ws" && catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 > "$OUT/logs/downstream_build.log" 2>&1 )
st=$?
[[ $st -ne 0 ]] && tail -n 30 "$OUT/logs/downstream_build.log"
result "a downstream catkin package builds against the installed package" $st
if [[ $st -eq 0 ]]; then
  "$ws/devel/lib/rc_downstream/label_room"
  result "the downstream program labels a box room with the installed core" $?
fi
