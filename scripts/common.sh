# Sourced by every script: one place for the environment the ROS 1 tools need on Debian 12.
# Debian's ROS lives in /usr; a pyenv python3 earlier on PATH lacks the ROS modules
# (catkin_pkg, rospkg), so /usr/bin must come first.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# RC_WS lets several builds coexist (e.g. a sanitizer build); default is the documented one.
WS="${RC_WS:-$REPO_ROOT/.catkin_ws}"
# The shared real frames (not shipped: a user's clone has none), beside the repository unless
# RC_SHARED names them (a worktree or clone elsewhere, which otherwise compared the fixtures only).
SHARED_REAL="${RC_SHARED:-$REPO_ROOT/../shared}/data/real"
export ROS_HOME="${ROS_HOME:-$WS/ros_home}"
export ROS_LOG_DIR="${ROS_LOG_DIR:-$ROS_HOME/log}"
export PYTHONDONTWRITEBYTECODE=1
rc_log() { printf '[ring_curvature] %s\n' "$*" >&2; }
rc_source_ws() {
  # setup.bash reads unset variables; relax nounset while sourcing it
  set +u; source "$WS/devel/setup.bash"; set -u
}
