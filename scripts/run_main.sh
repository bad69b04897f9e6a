#!/usr/bin/env bash
# The main job: set up, build, and run a headless ROS session in which the interface robot
# follows a square with the closed-loop path follower (launch/path_following.launch, IMU and
# camera noise, lockstep), records a bag and plots the reference and the actual head path.
# Outputs in out/main/: path_following.bag, path_following.png, summary.json.
# Extra roslaunch arguments are passed on, e.g. mode:=open_loop or
# overrides:=effects.interface_lateral_force.C_yr=1.4
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/build.sh"
source "$ROOT/scripts/ros_env.sh" "$ROOT/devel/setup.bash"
trap 'rm -rf "$ROS_TMP"' EXIT
OUT="$ROOT/out/main"
mkdir -p "$OUT"
rm -f "$OUT/path_following.bag" "$OUT/path_following.png" "$OUT/summary.json"
echo "run_main: master on $ROS_MASTER_URI; bag, plot and summary in $OUT"
roslaunch -p "$ROS_PORT" "$ROOT/launch/path_following.launch" record:=true \
  bag:="$OUT/path_following.bag" "$@"
/usr/bin/python3 "$ROOT/scripts/plot_path_following.py" "$OUT/path_following.bag" \
  --out "$OUT/path_following.png" --summary "$OUT/summary.json"
