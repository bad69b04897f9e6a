# Sourced by scripts and tests that run ROS: the workspace's devel space, a private master
# port on loopback and a temporary ROS_HOME (logs), so nothing touches ~/.ros or the network.
# Usage: source scripts/ros_env.sh [devel/setup.bash]   (default: this checkout's devel space)
# (pass the argument explicitly inside a script that has arguments of its own: a sourced file
# sees the caller's positional parameters)
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
set +u
# shellcheck disable=SC1090
source "${1:-$FLAGELLA_ROOT/devel/setup.bash}"
set -u
ROS_TMP="$(mktemp -d)"
ROS_PORT="$(/usr/bin/python3 "$FLAGELLA_ROOT/scripts/free_ros_port.py")"
export ROS_HOME="$ROS_TMP/ros_home" ROS_HOSTNAME=localhost ROS_MASTER_URI="http://localhost:$ROS_PORT"
mkdir -p "$ROS_HOME"
