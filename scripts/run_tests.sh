#!/usr/bin/env bash
# Set up, build, and run the whole test suite; exits non-zero on any failure and prints the
# test runner's summary.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "$FLAGELLA_ROOT/scripts/setup.sh"
bash "$FLAGELLA_ROOT/scripts/build.sh"
cd "$FLAGELLA_ROOT/build"
# rostest's masters and nodes on loopback only, their logs in a temporary ROS_HOME.
export ROS_HOSTNAME=localhost
ROS_HOME="$(mktemp -d)"
export ROS_HOME
trap 'rm -rf "$ROS_HOME"' EXIT
# ctest returns non-zero when any test fails (catkin_make run_tests alone would not).
ctest --output-on-failure -j"$(nproc)" "$@"
