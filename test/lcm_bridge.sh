#!/usr/bin/env bash
# The LCM bridge both ways, over LCM log files (no multicast): motor commands played from a log
# reach the simulator through ROS, and the simulator's states come back on LCM showing the
# commanded rate, then the failsafe stop after the commands end.
# Usage: lcm_bridge.sh <devel/setup.bash> <lcm_log_probe> [CONFIG OMEGA]
#   CONFIG: robot config (default: robot.launch's); OMEGA: commanded rate [rad/s] (default 7.5)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/ros_session.sh" "$1"
PROBE="$2"
CONFIG_ARGS=()
if [[ $# -ge 3 ]]; then CONFIG_ARGS=(config:="$3"); fi
OMEGA="${4:-7.5}"  # rad/s, inside the default 200 rpm limit
# 40 commands 0.05 s apart: 2 s of commands, played in wall time once the bridge starts.
"$PROBE" write-commands "$SESSION_TMP/commands.lcmlog" $OMEGA 40 0.05
timeout 120 roslaunch -p "$ROS_PORT" "$FLAGELLA_REPO/test/lcm_bridge_session.launch" \
  commands_log:="$SESSION_TMP/commands.lcmlog" output_log:="$SESSION_TMP/output.lcmlog" "${CONFIG_ARGS[@]}" \
  > "$SESSION_TMP/roslaunch.log" 2>&1 || { cat "$SESSION_TMP/roslaunch.log"; echo "FAIL: roslaunch"; exit 1; }
grep -h "flagella_sim: .* nodes, dt" "$SESSION_TMP/roslaunch.log" "$ROS_HOME"/log/*/*.log 2>/dev/null | head -1 || true
grep -h "messages to LCM" "$SESSION_TMP/roslaunch.log" "$ROS_HOME"/log/*/*lcm_bridge*.log 2>/dev/null | tail -1 || true
"$PROBE" check "$SESSION_TMP/output.lcmlog" $OMEGA
