#!/usr/bin/env bash
# The README's recording session, as fast as the machine goes: 60 s of simulated time at
# real_time_factor:=0 through scripts/roslaunch_session.py ends by itself (duration) with exit
# code 0 and no "REQUIRED process has died" banner, leaves a closed bag, and the bag holds every
# message the simulator published (counted per topic against the simulator's own final count and
# against rate x duration).
# Usage: recording.sh <devel/setup.bash>
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/ros_session.sh" "$1"
BAG="$SESSION_TMP/session.bag"
DURATION=60
rc=0
timeout 240 /usr/bin/python3 "$FLAGELLA_REPO/scripts/roslaunch_session.py" \
  "$FLAGELLA_REPO/launch/sim.launch" real_time_factor:=0 duration:=$DURATION record:=true \
  bag:="$BAG" > "$SESSION_TMP/roslaunch.log" 2>&1 || rc=$?
grep -a "simulated in\|messages written" "$SESSION_TMP/roslaunch.log" || true
if [ "$rc" != 0 ]; then cat "$SESSION_TMP/roslaunch.log"; echo "FAIL: the session exited $rc"; exit 1; fi
if grep -aq "REQUIRED process" "$SESSION_TMP/roslaunch.log"; then
  echo "FAIL: the session ended with roslaunch's REQUIRED banner"; exit 1
fi
if [ -e "$BAG.active" ] || [ ! -s "$BAG" ]; then
  ls -la "$SESSION_TMP"; echo "FAIL: no closed bag at $BAG"; exit 1
fi
/usr/bin/python3 "$FLAGELLA_REPO/test/check_recorded_bag.py" "$BAG" --duration $DURATION \
  --rate /flagella/rod_state=20 --rate /tf=20 --rate /flagella/imu=100 \
  --rate /flagella/markers=10 --rate /flagella/head_path=5 --rate /flagella/camera_fix=2 \
  --rate /diagnostics=1
