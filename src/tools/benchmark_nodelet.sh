#!/usr/bin/env bash
# Times the nodelet end to end in a real nodelet manager: starts a private ROS master on a free
# port (so it never meets another roscore), runs benchmark_nodelet against it, stops the master.
# usage: src/tools/benchmark_nodelet.sh --bag IN.bag [--repeat N] [--topic T]
# benchmark_nodelet is a lab tool: built with RC_LAB=1 if the workspace ($RC_WS) lacks it.
set -euo pipefail
source "$(dirname "$0")/../../scripts/common.sh"
rc_lab_tools benchmark_nodelet
rc_source_ws
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI="http://127.0.0.1:$port" ROS_IP=127.0.0.1
log="$ROS_LOG_DIR/benchmark_nodelet_master.log"
mkdir -p "$ROS_LOG_DIR"
rosmaster --core -p "$port" > "$log" 2>&1 &
master=$!
trap 'kill "$master" 2>/dev/null; wait "$master" 2>/dev/null || true' EXIT
for _ in $(seq 100); do
  rosnode list > /dev/null 2>&1 && break
  sleep 0.1
done
rosrun ring_curvature benchmark_nodelet "$@"
