#!/usr/bin/env bash
# A ROS user's session from the shell: scripts/ros_env.sh gives every shell the same master
# (FLAGELLA_ROS_PORT, default 11311), prints the export line and leaves the caller's set -u as it
# was; scripts/roslaunch_session.py passes exit codes through (a configuration error exits
# non-zero, a node that cannot be started is named and exits 1) without roslaunch's REQUIRED
# banner; relative config paths are taken from the directory roslaunch was started in;
# `roslaunch flagella_sim sim.launch` finds the launch file; two robots share one simulated time at
# real_time_factor:=0 (and the bag lands relative to the launch directory); a controller node with no simulator
# gives up after ~startup_timeout instead of waiting forever.
# Usage: session_start_and_end.sh <devel/setup.bash>
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/ros_session.sh" "$1"
fail() { echo "FAIL: $*" >&2; exit 1; }
SESSION="$FLAGELLA_REPO/scripts/roslaunch_session.py"

# 1. ros_env.sh: the port every shell agrees on, the export line, the caller's options kept.
out="$(env -u ROS_HOME -u FLAGELLA_ROS_PORT bash -c \
  'set +u; source "$0/scripts/ros_env.sh"; echo "uri=$ROS_MASTER_URI home=$ROS_HOME flags=$-"' \
  "$FLAGELLA_REPO" 2>&1)"
[[ "$out" == *"uri=http://localhost:11311 "* ]] || fail "default port is not 11311: $out"
[[ "$out" == *"home=$FLAGELLA_REPO/out/ros_home "* ]] || fail "default ROS_HOME: $out"
[[ "$out" == *"export ROS_MASTER_URI=http://localhost:11311"* ]] || fail "no export line: $out"
[[ "$out" != *flags=*u* ]] || fail "ros_env.sh turned on set -u in the caller: $out"
out="$(FLAGELLA_ROS_PORT=24680 bash -c 'set -u; source "$0/scripts/ros_env.sh" 2>/dev/null; echo "uri=$ROS_MASTER_URI flags=$-"' "$FLAGELLA_REPO")"
[[ "$out" == *"uri=http://localhost:24680 "* ]] || fail "FLAGELLA_ROS_PORT ignored: $out"
[[ "$out" == *flags=*u* ]] || fail "ros_env.sh turned off the caller's set -u: $out"
status=0
out="$(FLAGELLA_ROS_PORT=abc bash -c 'source "$0/scripts/ros_env.sh"' "$FLAGELLA_REPO" 2>&1)" || status=$?
[[ "$status" == 2 && "$out" == *"FLAGELLA_ROS_PORT must be a port number in [1024, 65535], got 'abc'"* ]] ||
  fail "bad FLAGELLA_ROS_PORT: exit $status: $out"
echo "ok: ros_env.sh"

expect_session() {  # expected status, expected text, directory, launch arguments...
  local want="$1" text="$2" dir="$3"
  shift 3
  local out status=0
  out="$(cd "$dir" && timeout 120 /usr/bin/python3 "$SESSION" "$@" 2>&1)" || status=$?
  [[ "$status" == "$want" ]] || fail "'$*' in $dir exited $status, expected $want: $out"
  [[ "$out" == *"$text"* ]] || fail "'$*' in $dir did not print '$text': $out"
  [[ "$out" != *"REQUIRED process"* ]] || fail "'$*' ended with the REQUIRED banner"
  echo "ok: '$*' in $dir -> $status"
}

# 2. Exit codes passed through.
expect_session 0 "flagella/sim ended the session, exit code 0" "$FLAGELLA_REPO" \
  launch/sim.launch duration:=1 real_time_factor:=0
expect_session 2 "initial_motor must be \"config\" or \"stopped\", got \"foo\"" "$FLAGELLA_REPO" \
  launch/sim.launch initial_motor:=foo
# 3. Relative config paths: from the directory the session was started in.
expect_session 0 "config/granular_design2.yaml" "$FLAGELLA_REPO" \
  launch/sim.launch config:=config/granular_design2.yaml duration:=1 real_time_factor:=0
expect_session 2 "$SESSION_TMP/config/granular_design2.yaml: cannot open the config file" \
  "$SESSION_TMP" "$FLAGELLA_REPO/launch/sim.launch" config:=config/granular_design2.yaml duration:=1
# 3b. Two robots as fast as possible: the clock leader waits for the follower at every step, so
# both simulate the whole duration (the follower used to start after the leader had finished).
expect_session 0 "robot_a/sim ended the session, exit code 0" "$SESSION_TMP" \
  "$FLAGELLA_REPO/launch/multi_robot.launch" real_time_factor:=0 duration:=5 record:=true bag:=multi.bag
/usr/bin/python3 - "$SESSION_TMP/multi.bag" <<'PY' || fail "multi_robot: the robots did not share the duration"
import sys, rosbag
last = {}
with rosbag.Bag(sys.argv[1]) as bag:
    for topic, msg, _ in bag.read_messages(topics=["/robot_a/imu", "/robot_b/imu"]):
        last[topic] = msg.header.stamp.to_sec()
print("multi_robot: last IMU stamps", last)
sys.exit(0 if all(abs(last.get(t, -1) - 5.0) < 1e-6 for t in ("/robot_a/imu", "/robot_b/imu")) else 1)
PY
# 4. A shell without the workspace: the node is named, exit 1, no wait for a clock.
out="$(cd "$SESSION_TMP" && env -i PATH=/usr/bin:/bin HOME="$SESSION_TMP" ROS_HOME="$ROS_HOME" \
  ROS_MASTER_URI="$ROS_MASTER_URI" ROS_HOSTNAME=localhost \
  timeout 120 /usr/bin/python3 "$SESSION" "$FLAGELLA_REPO/launch/sim.launch" duration:=1 2>&1)" &&
  fail "a session without the workspace exited 0: $out"
[[ "$out" == *"could not start"*"devel/setup.bash"* ]] || fail "unbuilt node not named: $out"
echo "ok: a node that cannot be started is named"
# 5. The package's launch file.
# (the list is read whole first: grep -q closing the pipe at its first match made roslaunch die
# of a broken pipe, and pipefail failed the check now and then)
files="$(roslaunch --files flagella_sim sim.launch)" || fail "roslaunch --files flagella_sim sim.launch failed"
[[ "$files" == *"sim.launch"* ]] || fail "roslaunch flagella_sim sim.launch: not found in: $files"
echo "ok: roslaunch flagella_sim sim.launch"
# 6. A controller without a simulator gives up.
roscore -p "$ROS_PORT" > "$SESSION_TMP/roscore.log" 2>&1 &
SESSION_PIDS+=($!)
for _ in $(seq 50); do rostopic list > /dev/null 2>&1 && break; sleep 0.2; done
status=0
out="$(timeout 60 rosrun flagella_control flagella_path_follower _startup_timeout:=1 \
  _base_directory:="$FLAGELLA_REPO" _calibration:=config/calibration/interface_path_planning.yaml \
  _path:=config/paths/square.yaml 2>&1)" || status=$?
[[ "$status" == 1 && "$out" == *"no IMU sample on /imu within 1 wall s"* ]] ||
  fail "path follower without a simulator: exit $status: $out"
echo "ok: the path follower gives up without a simulator"
echo "PASS: sessions start and end as a shell user expects"
