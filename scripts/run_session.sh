#!/usr/bin/env bash
# Set up, build, and run a headless ROS session: roslaunch launch/sim.launch on a private
# loopback master (FLAGELLA_ROS_PORT, default 11311; logs in out/ros_home). Any roslaunch
# arguments are passed on, e.g.
#   bash scripts/run_session.sh real_time_factor:=0 duration:=60 record:=true bag:=/tmp/run.bag
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/build.sh"
source "$ROOT/scripts/ros_env.sh" "$ROOT/devel/setup.bash"
# ends when the simulator ends (duration:=T), with its exit code
exec /usr/bin/python3 "$ROOT/scripts/roslaunch_session.py" "$ROOT/launch/sim.launch" "$@"
