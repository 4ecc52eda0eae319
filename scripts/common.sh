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
# The lab's targets (RC_BUILD_LAB: cmake/lab.cmake) in $WS, for the benchmark and A/B scripts
# and the suites that use them: builds the targets named (scripts/build with RC_LAB=1) when the
# workspace was configured without the lab or one of them is missing.
rc_lab_tools() {
  local t need=0
  grep -qx 'RC_BUILD_LAB:BOOL=ON' "$WS/build/CMakeCache.txt" 2>/dev/null || need=1
  for t in "$@"; do
    [[ -e "$WS/devel/lib/ring_curvature/$t" || -e "$WS/devel/lib/lib$t.so" ]] || need=1
  done
  [[ $need -eq 0 ]] || RC_LAB=1 "$REPO_ROOT/scripts/build" "$@" >&2
}
rc_source_ws() {
  # setup.bash reads unset variables; relax nounset while sourcing it
  set +u; source "$WS/devel/setup.bash"; set -u
}
# For the suites in scripts/test.d: runs a check (its name, then a command that must succeed),
# prints "ok" or "FAIL" with the name and counts it in the caller's $passed / $failed.
rc_check() {
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "ok    $name"; else failed=$((failed + 1)); echo "FAIL  $name"; fi
}
