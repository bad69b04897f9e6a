#!/usr/bin/env bash
# The README's recording session: `roslaunch launch/sim.launch record:=true` ends by itself
# (duration), leaves a closed bag, and the bag holds every message the simulator published
# (counted per topic against the simulator's own final count and against rate x duration).
# Usage: recording.sh <devel/setup.bash>
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/ros_session.sh" "$1"
BAG="$SESSION_TMP/session.bag"
DURATION=10
# rosbag record subscribes with a fixed queue of 100 messages: at 30x real time (about 4800
# messages/s) it drops some on a busy 2-core machine, at 5x (800/s) it keeps up.
REAL_TIME_FACTOR=5
timeout 240 roslaunch -p "$ROS_PORT" "$FLAGELLA_REPO/launch/sim.launch" \
  real_time_factor:=$REAL_TIME_FACTOR duration:=$DURATION record:=true bag:="$BAG" \
  > "$SESSION_TMP/roslaunch.log" 2>&1 || { cat "$SESSION_TMP/roslaunch.log"; echo "FAIL: roslaunch"; exit 1; }
grep "simulated in" "$SESSION_TMP/roslaunch.log" || true
if [ -e "$BAG.active" ] || [ ! -s "$BAG" ]; then
  ls -la "$SESSION_TMP"; echo "FAIL: no closed bag at $BAG"; exit 1
fi
/usr/bin/python3 "$FLAGELLA_REPO/test/check_recorded_bag.py" "$BAG" --duration $DURATION \
  --rate /flagella/rod_state=20 --rate /tf=20 --rate /flagella/imu=100 \
  --rate /flagella/markers=10 --rate /flagella/head_path=5 --rate /diagnostics=1
