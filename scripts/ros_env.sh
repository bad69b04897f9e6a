# Sourced by you and by the scripts and tests that run ROS: the workspace's devel space, a master
# on loopback at a port every terminal agrees on, and a ROS_HOME (logs, the nodes' working
# directory) that outlives the session, so the log named in an error message is still there.
#   FLAGELLA_ROS_PORT  the master's port (default 11311, ROS's own); the tests set a free one each
#   ROS_HOME           kept when already set, else <repository>/out/ros_home
# Prints the export line that points another shell at the same master. Leaves the caller's shell
# options (set -u) as they were.
# Usage: source scripts/ros_env.sh [devel/setup.bash]   (default: this checkout's devel space)
# (pass the argument explicitly inside a script that has arguments of its own: a sourced file
# sees the caller's positional parameters)
case $- in *u*) ros_env_had_nounset=1 ;; *) ros_env_had_nounset=0 ;; esac
set +u
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
# shellcheck disable=SC1090
source "${1:-$FLAGELLA_ROOT/devel/setup.bash}"
ROS_PORT="${FLAGELLA_ROS_PORT:-11311}"
if [[ ! "$ROS_PORT" =~ ^[0-9]+$ ]] || ((ROS_PORT < 1024 || ROS_PORT > 65535)); then
  echo "ros_env: FLAGELLA_ROS_PORT must be a port number in [1024, 65535], got '$ROS_PORT'" >&2
  if [ "$ros_env_had_nounset" = 1 ]; then set -u; fi
  unset ros_env_had_nounset
  return 2
fi
export ROS_HOME="${ROS_HOME:-$FLAGELLA_ROOT/out/ros_home}" ROS_HOSTNAME=localhost
export ROS_MASTER_URI="http://localhost:$ROS_PORT"
mkdir -p "$ROS_HOME"
echo "ros_env: master $ROS_MASTER_URI, logs in $ROS_HOME; another shell reaches it with" \
  "'source scripts/ros_env.sh' or: export ROS_MASTER_URI=$ROS_MASTER_URI ROS_HOSTNAME=localhost" >&2
if [ "$ros_env_had_nounset" = 1 ]; then set -u; fi
unset ros_env_had_nounset
