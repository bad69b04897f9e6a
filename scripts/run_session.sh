#!/usr/bin/env bash
# Set up, build, and run a headless ROS session: roslaunch launch/sim.launch on a private
# loopback master. Any roslaunch arguments are passed on, e.g.
#   bash scripts/run_session.sh real_time_factor:=0 duration:=60 record:=true bag:=/tmp/run.bag
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/build.sh"
source "$ROOT/scripts/ros_env.sh" "$ROOT/devel/setup.bash"
trap 'rm -rf "$ROS_TMP"' EXIT
echo "run_session: master on $ROS_MASTER_URI, logs in $ROS_HOME (removed at exit)"
roslaunch -p "$ROS_PORT" "$ROOT/launch/sim.launch" "$@"
