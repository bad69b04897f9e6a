# Sourced by the shell tests: the ROS environment of scripts/ros_env.sh on a private master (a
# free port, a temporary ROS_HOME) plus cleanup of everything the test started, even on failure.
# Usage: source ros_session.sh <devel/setup.bash>
SESSION_TMP="$(mktemp -d)"
export ROS_HOME="$SESSION_TMP/ros_home"
FLAGELLA_ROS_PORT="$(/usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/../scripts/free_ros_port.py")"
export FLAGELLA_ROS_PORT
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/ros_env.sh" "$1" 2>/dev/null
FLAGELLA_REPO="$FLAGELLA_ROOT"
SESSION_PIDS=()
cleanup_session() {
  for pid in "${SESSION_PIDS[@]}"; do kill -INT -- "-$pid" 2>/dev/null || kill -INT "$pid" 2>/dev/null || true; done
  sleep 1
  for pid in "${SESSION_PIDS[@]}"; do kill -KILL -- "-$pid" 2>/dev/null || kill -KILL "$pid" 2>/dev/null || true; done
  if [ "${KEEP_SESSION_TMP:-0}" = 1 ]; then echo "kept: $SESSION_TMP"; else rm -rf "$SESSION_TMP"; fi
}
trap cleanup_session EXIT
