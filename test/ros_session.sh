# Sourced by the shell tests: a private ROS environment on loopback (own master port and
# ROS_HOME in a temporary folder) and cleanup of everything started, even on failure.
# Usage: source ros_session.sh <devel/setup.bash>
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
set +u
# shellcheck disable=SC1090
source "$1"
set -u
FLAGELLA_REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SESSION_TMP="$(mktemp -d)"
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
ROS_PORT="$(free_port)"
export ROS_HOME="$SESSION_TMP/ros_home" ROS_HOSTNAME=localhost ROS_MASTER_URI="http://localhost:$ROS_PORT"
mkdir -p "$ROS_HOME"
SESSION_PIDS=()
cleanup_session() {
  for pid in "${SESSION_PIDS[@]}"; do kill -INT -- "-$pid" 2>/dev/null || kill -INT "$pid" 2>/dev/null || true; done
  sleep 1
  for pid in "${SESSION_PIDS[@]}"; do kill -KILL -- "-$pid" 2>/dev/null || kill -KILL "$pid" 2>/dev/null || true; done
  if [ "${KEEP_SESSION_TMP:-0}" = 1 ]; then echo "kept: $SESSION_TMP"; else rm -rf "$SESSION_TMP"; fi
}
trap cleanup_session EXIT
