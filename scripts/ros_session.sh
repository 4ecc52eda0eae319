# Sourced by scripts/demo and scripts/test.d/30-rviz-screenshot: a private ROS session (own
# roscore port, own X display) whose every process is started here and stopped on exit.
# Each background process gets its own process group (setsid), so stopping it also stops the
# children it spawned (roslaunch -> nodes, rosbag record -> record), and nothing else.

RS_PIDS=()

# rs_start LOGFILE CMD...: run CMD in the background in a new process group.
rs_start() {
  local log=$1; shift
  setsid "$@" >"$log" 2>&1 < /dev/null &
  RS_PIDS+=($!)
  RS_LAST_PID=$!
}

# rs_stop_all: newest first, SIGINT each group (rosbag record closes its bag cleanly on SIGINT)
# and wait for it, SIGKILL after a grace period. One at a time, so rviz is gone before its X
# server is. Safe to call twice.
rs_stop_all() {
  local pid i
  for ((i = ${#RS_PIDS[@]} - 1; i >= 0; i--)); do
    pid=${RS_PIDS[i]}
    kill -INT -- "-$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- "-$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  RS_PIDS=()
}

# rs_free_port FIRST: first TCP port >= FIRST that nothing listens on.
rs_free_port() {
  local p=$1
  while (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; do p=$((p + 1)); done
  echo "$p"
}

# rs_roscore PORT LOGDIR: start a roscore on PORT, export ROS_MASTER_URI, wait until it answers.
rs_roscore() {
  local port=$1 logdir=$2
  export ROS_MASTER_URI="http://127.0.0.1:$port"
  export ROS_IP=127.0.0.1
  rs_start "$logdir/roscore.log" roscore -p "$port"
  for _ in $(seq 100); do
    rosparam get /run_id >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  echo "roscore did not come up on port $port; see $logdir/roscore.log" >&2
  return 1
}

# rs_xvfb LOGDIR: start Xvfb on the first free display from :99 down, export DISPLAY.
rs_xvfb() {
  local logdir=$1 d=99
  while [[ -e /tmp/.X11-unix/X$d || -e /tmp/.X$d-lock ]]; do d=$((d - 1)); done
  rs_start "$logdir/xvfb.log" Xvfb ":$d" -screen 0 1280x800x24 -nolisten tcp
  export DISPLAY=":$d"
  for _ in $(seq 50); do [[ -e /tmp/.X11-unix/X$d ]] && return 0; sleep 0.1; done
  echo "Xvfb did not start on :$d; see $logdir/xvfb.log" >&2
  return 1
}

# rs_wait_subscribers TOPIC N TIMEOUT_S [PID...]: wait until TOPIC has at least N subscribers;
# give up early when one of the PIDs (the processes expected to subscribe) has died.
rs_wait_subscribers() {
  local topic=$1 n=$2 timeout=$3 count pid
  shift 3
  local end=$((SECONDS + timeout))
  while ((SECONDS < end)); do
    count=$(rostopic info "$topic" 2>/dev/null | sed -n '/^Subscribers:/,$p' | grep -c '^ \* ' || true)
    ((count >= n)) && return 0
    for pid in "$@"; do
      kill -0 "$pid" 2>/dev/null || { echo "process $pid exited while waiting for subscribers on $topic" >&2; return 1; }
    done
    sleep 0.3
  done
  echo "timed out waiting for $n subscribers on $topic" >&2
  return 1
}

# rs_nodelet LOGDIR NAME: launch/ring_curvature.launch, which starts a manager NAME_manager and
# loads the nodelet NAME into it; outputs are /NAME/labelled_points etc., input /velodyne_points.
rs_nodelet() {
  local logdir=$1 name=$2
  rs_start "$logdir/nodelet.log" roslaunch --wait ring_curvature ring_curvature.launch name:="$name"
}
