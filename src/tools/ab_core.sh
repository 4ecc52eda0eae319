#!/usr/bin/env bash
# In-process A/B timing of two builds of the core: one process, both builds loaded side by side
# (src/tools/ab_core.cpp), alternating frame by frame on the same frames, so that both see the
# same machine state. Prints per build the median of each stage and of the whole call, and B/A
# as the median and 10-90 % range over rounds of each round's median frame-pair ratio.
# usage: ab_core.sh A_DIR B_DIR BAG [ROUNDS] [extra ab_core args, e.g. --passes 10 --topic T]
#   A build against itself with an environment switch on one side: the same folder twice and
#   --b-env NAME=VALUE (set for that side's first call). Run A B, then B A: both orders.
#   *_DIR holds a build's libring_curvature_core.so (copied out of a workspace's devel/lib), and
#   if it was built with one, its libring_curvature_ab_shim.so. For a build without a shim, one
#   is compiled here against the headers in the directory named by AB_A_INCLUDE / AB_B_INCLUDE
#   if set, else in *_DIR/include if there is one, else this repository's include/. Those must
#   be the build's own headers: Pipeline holds the grid builder and the other stages by value,
#   so a change to any private member of the core's headers changes its layout, and a shim
#   compiled against other headers crashes (free(): invalid pointer) or worse. For an old
#   commit: git archive COMMIT include | tar -x -C DIR.
# ab_core itself comes from this repository's workspace, built with the lab (RC_LAB=1
# scripts/build) here if missing; AB_CORE_BIN overrides.
set -euo pipefail
source "$(dirname "$0")/../../scripts/common.sh"
if (( $# < 3 )); then
  sed -n '2,15p' "$0" >&2
  exit 2
fi
a_dir=$1 b_dir=$2 bag=$3 rounds=${4:-20}
shift $(( $# < 4 ? $# : 4 ))
[[ -n "${AB_CORE_BIN:-}" ]] || rc_lab_tools ab_core
bin=${AB_CORE_BIN:-$WS/devel/lib/ring_curvature/ab_core}
[[ -x "$bin" ]] || { rc_log "no $bin: build it (RC_LAB=1 scripts/build ab_core)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Prints the shim to use for build folder $1 (side $2: A or B), compiling one if needed.
shim_for() {
  local dir=$1 side=$2 inc_var="AB_${2}_INCLUDE"
  [[ -f "$dir/libring_curvature_core.so" ]] || { rc_log "$dir holds no libring_curvature_core.so"; return 1; }
  if [[ -f "$dir/libring_curvature_ab_shim.so" ]]; then
    rc_log "$side: shim of the build: $dir/libring_curvature_ab_shim.so"
    echo "$dir/libring_curvature_ab_shim.so"
    return
  fi
  local inc="$REPO_ROOT/include"
  [[ -d "$dir/include" ]] && inc="$dir/include"
  [[ -n "${!inc_var:-}" ]] && inc=${!inc_var}
  rc_log "$side: compiling a shim against $inc"
  # The project's warning flags; --no-undefined: every symbol the shim needs must come from this
  # build's core (or the C++ runtime), checked now rather than at load time.
  g++ -std=c++17 -O2 -fPIC -shared -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Werror \
    -I"$inc" -I/usr/include/eigen3 "$REPO_ROOT/src/tools/ab_shim.cpp" -o "$tmp/shim_$side.so" \
    -L"$dir" -l:libring_curvature_core.so -Wl,--no-undefined >&2
  echo "$tmp/shim_$side.so"
}
a_shim=$(shim_for "$a_dir" A)
b_shim=$(shim_for "$b_dir" B)
"$bin" --a-core "$a_dir/libring_curvature_core.so" --a-shim "$a_shim" \
  --b-core "$b_dir/libring_curvature_core.so" --b-shim "$b_shim" --bag "$bag" --rounds "$rounds" "$@"
