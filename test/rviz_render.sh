#!/usr/bin/env bash
# End-to-end check: "a recorded bag played into rviz under Xvfb renders the rods".
#
#   bash test/rviz_render.sh /work/main/devel/setup.bash [steering]
#
# With "steering": the session is launch/steering_3d.launch record:=true (the helical robot, 40 s
# of simulated time: the waypoints appear once the start frame's course is measured), the bag
# must hold the rod and slider markers, the waypoints and /tf_static, and the replay is the
# README's (rviz/steering_3d.rviz, as launch/replay.launch view:=steering_3d): the flagellum
# (tail-0 colour) must render.
#
# 1. records a 3 s (simulated) session with launch/sim.launch (as fast as possible) into a bag;
# 2. starts a private roscore (loopback, free port, temporary ROS_HOME, /use_sim_time true),
#    a private Xvfb (1280x800x24, display picked by Xvfb itself) and rviz -d rviz/flagella.rviz;
# 3. takes blank.png once rviz has settled, before any data is played;
# 4. plays the bag (rosbag play --clock --loop) and takes shot.png;
# 5. pixel check on the same screenshot: pixels changed w.r.t. blank.png (compare -metric AE)
#    and pixels of the tail-0 colour (markers ns "tails" id 0, RGB (0.95,0.45,0.10)).
#
# Exit 0 = pass. Non-zero on any failure (no bag, bag still .active, rviz crashed, too few
# pixels, timeouts). Screenshots go to $FLAGELLA_TEST_ARTIFACTS if set; otherwise they stay in
# the temp dir, which is printed (and kept) on failure and deleted on success.
#
# Thresholds (measured on a 2-core VM, Xvfb + Mesa llvmpipe, rviz 1.14.19, design 1 config,
# 20 screenshots over ~7 loops of the bag):
#   blank vs shot AE (fuzz 10%): 33400..36500 with rods + tf axes; the blank itself (grid only)
#     is the reference (0); tf axes + head path alone (bag filtered without /flagella/markers)
#     give 2300..6500.                                      -> MIN_CHANGED_PIXELS=15000
#   tail-0 colour (fuzz 15% around (242,115,26)): 7800..8000 with rods (the line strips are
#     unlit, drawn exactly (242,114,25)); 0 in the blank and 0 with tf + path only.
#                                                           -> MIN_TAIL_PIXELS=2500
# See the report printed by the script for the values of a run.

set -u -o pipefail

SETUP_BASH=${1:-}
SESSION=${2:-sim}
MIN_CHANGED_PIXELS=${MIN_CHANGED_PIXELS:-15000}
MIN_TAIL_PIXELS=${MIN_TAIL_PIXELS:-2500}
TAIL_RGB="rgb(242,115,26)"
TAIL_FUZZ="15%"
DIFF_FUZZ="10%"

export PATH=/usr/bin:/bin:$PATH  # system python3 has the ROS modules; ImageMagick from /usr/bin
IMPORT=/usr/bin/import
CONVERT=/usr/bin/convert
COMPARE=/usr/bin/compare

log() { echo "[rviz_render] $*"; }
START_TIME=$(date +%s)

# ---------------------------------------------------------------------------- setup / cleanup
TMP=$(mktemp -d -t flagella_rviz_render.XXXXXX)
PIDS=()          # background process group leaders (started with setsid)
RESULT=1         # becomes 0 only when every check passed

kill_groups() {
  local pid
  for pid in "${PIDS[@]:-}"; do
    [ -n "$pid" ] || continue
    kill -TERM -- "-$pid" 2>/dev/null || kill -TERM "$pid" 2>/dev/null
  done
  # give them up to ~3 s to go, then SIGKILL what is left
  local i alive
  for i in $(seq 30); do
    alive=0
    for pid in "${PIDS[@]:-}"; do
      [ -n "$pid" ] && kill -0 -- "-$pid" 2>/dev/null && alive=1
    done
    [ $alive = 0 ] && break
    sleep 0.1
  done
  for pid in "${PIDS[@]:-}"; do
    [ -n "$pid" ] || continue
    kill -KILL -- "-$pid" 2>/dev/null
  done
  PIDS=()
  wait 2>/dev/null
}

cleanup() {
  local rc=$?
  trap - EXIT INT TERM HUP
  kill_groups
  if [ -n "${FLAGELLA_TEST_ARTIFACTS:-}" ]; then
    mkdir -p "$FLAGELLA_TEST_ARTIFACTS" &&
      cp -f "$TMP"/*.png "$TMP"/*.log "$FLAGELLA_TEST_ARTIFACTS"/ 2>/dev/null
    log "artifacts in $FLAGELLA_TEST_ARTIFACTS"
  fi
  if [ "$RESULT" = 0 ] && [ "$rc" = 0 ]; then
    rm -rf "$TMP"
  else
    log "FAILED; screenshots and logs kept in $TMP"
    [ "$rc" = 0 ] && rc=1
  fi
  log "took $(( $(date +%s) - START_TIME )) s"
  exit "$rc"
}
trap cleanup EXIT
trap 'log "interrupted"; exit 130' INT
trap 'log "terminated"; exit 143' TERM HUP

fail() { log "FAIL: $*"; exit 1; }

# Starts "$@" in a new session (own process group, pgid = pid) in the background.
# Non-interactive bash does not make background jobs group leaders, so setsid does not fork
# and $! is the new group's id.
spawn() {
  local out=$1; shift
  setsid "$@" >"$out" 2>&1 </dev/null &
  LAST_PID=$!
  PIDS+=("$LAST_PID")
}

free_port() {
  python3 "$(dirname "${BASH_SOURCE[0]}")/../scripts/free_ros_port.py"
}

# wait_for TIMEOUT_S DESCRIPTION CMD... : polls CMD every 0.25 s
wait_for() {
  local timeout=$1 what=$2; shift 2
  local deadline=$(( $(date +%s) + timeout ))
  until "$@" >/dev/null 2>&1; do
    [ "$(date +%s)" -lt "$deadline" ] || fail "timed out after ${timeout}s waiting for $what"
    sleep 0.25
  done
}

# ---------------------------------------------------------------------------- environment
[ -n "$SETUP_BASH" ] || fail "usage: $0 <devel>/setup.bash"
[ -f "$SETUP_BASH" ] || fail "no such setup.bash: $SETUP_BASH"
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
case "$SESSION" in
  sim)
    SIM_LAUNCH=$REPO/launch/sim.launch
    RVIZ_CONFIG=$REPO/rviz/flagella.rviz
    LAUNCH_ARGS=(real_time_factor:=0 duration:=3)
    BAG_TOPICS=(/flagella/markers)
    RECORD_LIMIT=90
    ;;
  steering)
    SIM_LAUNCH=$REPO/launch/steering_3d.launch
    RVIZ_CONFIG=$REPO/rviz/steering_3d.rviz
    LAUNCH_ARGS=(max_duration:=40)
    BAG_TOPICS=(/flagella/markers /flagella/slider_marker /flagella/waypoint_markers /tf_static)
    RECORD_LIMIT=240
    ;;
  *) fail "usage: $0 <devel>/setup.bash [sim|steering]" ;;
esac
[ -f "$SIM_LAUNCH" ] || fail "missing $SIM_LAUNCH"
[ -f "$RVIZ_CONFIG" ] || fail "missing $RVIZ_CONFIG"
for tool in Xvfb xwininfo setsid python3 "$IMPORT" "$CONVERT" "$COMPARE"; do
  command -v "$tool" >/dev/null || fail "missing tool: $tool"
done

set +u
# shellcheck disable=SC1090
source "$SETUP_BASH" || fail "sourcing $SETUP_BASH failed"
set -u
for tool in roslaunch roscore rosparam rosbag rviz; do
  command -v "$tool" >/dev/null || fail "missing ROS tool: $tool"
done

export ROS_HOME=$TMP/ros_home
export ROS_LOG_DIR=$ROS_HOME/log
mkdir -p "$ROS_LOG_DIR"
export ROS_HOSTNAME=localhost
unset ROS_IP
log "temp dir $TMP"

# ---------------------------------------------------------------------------- 1. record a bag
BAG=$TMP/session.bag
PORT=$(free_port) || fail "no free port"
export ROS_MASTER_URI=http://localhost:$PORT
log "recording a $SESSION session (${LAUNCH_ARGS[*]}) into $BAG (master port $PORT)"
spawn "$TMP/record.log" timeout -s INT -k 10 "$RECORD_LIMIT" \
  roslaunch -p "$PORT" "$SIM_LAUNCH" "${LAUNCH_ARGS[@]}" record:=true bag:="$BAG"
REC_PID=$LAST_PID
wait "$REC_PID"
REC_RC=$?
[ "$REC_RC" = 0 ] || { tail -n 30 "$TMP/record.log"; fail "recording roslaunch exited with $REC_RC"; }
# roslaunch stops the recorder (SIGINT) before it exits; the recorder then renames
# session.bag.active -> session.bag. Allow a few seconds for that on a slow machine.
deadline=$(( $(date +%s) + 15 ))
while [ -e "$BAG.active" ] && [ "$(date +%s)" -lt "$deadline" ]; do sleep 0.25; done
[ -e "$BAG.active" ] && fail "bag was not closed: $BAG.active still exists (recorder killed?)"
[ -f "$BAG" ] || { tail -n 30 "$TMP/record.log"; fail "bag $BAG is missing (recording failed)"; }
[ -s "$BAG" ] || fail "bag $BAG is empty"
BAG_INFO=$(rosbag info "$BAG" 2>&1) || { echo "$BAG_INFO"; fail "rosbag info failed on $BAG"; }
for topic in "${BAG_TOPICS[@]}"; do
  MSGS=$(echo "$BAG_INFO" | awk -v t="$topic" '$1 == t {print $2}')
  if [ -z "$MSGS" ] || [ "$MSGS" -lt 1 ]; then
    echo "$BAG_INFO"; fail "bag has no $topic messages"
  fi
  log "bag has $MSGS messages on $topic"
done
log "bag ok: $(du -k "$BAG" | cut -f1) kB"

# ---------------------------------------------------------------------------- 2. master, X, rviz
PORT=$(free_port) || fail "no free port"
export ROS_MASTER_URI=http://localhost:$PORT
spawn "$TMP/roscore.log" roscore -p "$PORT"
CORE_PID=$LAST_PID
wait_for 30 "roscore on port $PORT" rosparam set /use_sim_time true
kill -0 "$CORE_PID" 2>/dev/null || fail "roscore died (see $TMP/roscore.log)"
[ "$(rosparam get /use_sim_time)" = "true" ] || fail "could not set /use_sim_time"

# Xvfb picks a free display itself and writes its number to fd 3 once it accepts connections
spawn "$TMP/xvfb.log" Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp 3>"$TMP/display"
XVFB_PID=$LAST_PID
wait_for 20 "Xvfb" bash -c "[ -s '$TMP/display' ]"
DISPLAY=:$(head -n1 "$TMP/display" | tr -dc 0-9)
export DISPLAY
kill -0 "$XVFB_PID" 2>/dev/null || fail "Xvfb died (see $TMP/xvfb.log)"
export LIBGL_ALWAYS_SOFTWARE=1
export QT_X11_NO_MITSHM=1
export XDG_RUNTIME_DIR=$TMP/xdg
mkdir -m 700 "$XDG_RUNTIME_DIR"
log "Xvfb on DISPLAY=$DISPLAY, master $ROS_MASTER_URI"

spawn "$TMP/rviz.log" rviz -d "$RVIZ_CONFIG"
RVIZ_PID=$LAST_PID
rviz_alive() {
  kill -0 "$RVIZ_PID" 2>/dev/null ||
    { tail -n 30 "$TMP/rviz.log"; fail "rviz is not running any more (crashed?), see $TMP/rviz.log"; }
}
rviz_window() { xwininfo -root -tree 2>/dev/null | grep -q 'RViz"'; }
deadline=$(( $(date +%s) + 60 ))
until rviz_window; do
  rviz_alive
  [ "$(date +%s)" -lt "$deadline" ] || fail "no rviz window after 60 s"
  sleep 0.5
done
log "rviz window is up after $(( $(date +%s) - START_TIME )) s"

shoot() { "$IMPORT" -window root "$1" 2>>"$TMP/import.log"; }
# number of pixels that differ between two images (fuzz $3)
changed_pixels() {
  local out
  out=$("$COMPARE" -precision 12 -metric AE -fuzz "$3" "$1" "$2" "${4:-null:}" 2>&1 >/dev/null)
  # compare exits 1 when images differ; the count is on stderr
  echo "${out%%[!0-9.]*}" | cut -d. -f1
}
# number of pixels within $TAIL_FUZZ of the tail-0 colour
tail_pixels() {
  "$CONVERT" "$1" -alpha off -fuzz "$TAIL_FUZZ" -transparent "$TAIL_RGB" -alpha extract -negate \
    -precision 12 -format '%[fx:round(mean*w*h)]' info:
}

# number of pixels within fuzz $3 of colour $2
colour_pixels() {
  "$CONVERT" "$1" -alpha off -fuzz "$3" -transparent "$2" -alpha extract -negate \
    -precision 12 -format '%[fx:round(mean*w*h)]' info:
}
WAYPOINT_RGB="rgb(100,74,42)"
WAYPOINT_FUZZ="8%"
MIN_WAYPOINT_PIXELS=${MIN_WAYPOINT_PIXELS:-3000}  # measured: 320-380 before they appear (the helix's shading), 12060 after

# grey grid lines on the (48,48,48) background: (62..104, 62..104, 63..106); none before the
# 3D view has rendered (measured ~16000 within 10% of (90,90,92) for the configured view)
grid_pixels() {
  "$CONVERT" "$1" -alpha off -fuzz 10% -transparent "rgb(90,90,92)" -alpha extract -negate \
    -precision 12 -format '%[fx:round(mean*w*h)]' info:
}
MIN_GRID_PIXELS=2000

# blank: wait until the 3D view has rendered the grid and is settled (two consecutive
# screenshots nearly equal; the status bar's fps counter may change a few hundred pixels)
prev=""
deadline=$(( $(date +%s) + 30 ))
i=0
while :; do
  rviz_alive
  i=$((i + 1))
  shoot "$TMP/blank_$i.png" || true
  if [ -n "$prev" ] && [ -s "$TMP/blank_$i.png" ]; then
    d=$(changed_pixels "$prev" "$TMP/blank_$i.png" 0%)
    g=$(grid_pixels "$TMP/blank_$i.png")
    [ -n "$d" ] && [ "$d" -lt 1000 ] && [ "${g:-0}" -ge "$MIN_GRID_PIXELS" ] && break
  fi
  [ -s "$TMP/blank_$i.png" ] && prev=$TMP/blank_$i.png
  [ "$(date +%s)" -lt "$deadline" ] || fail "rviz did not settle for a blank screenshot in 30 s"
  sleep 1
done
mv "$TMP/blank_$i.png" "$TMP/blank.png"
rm -f "$TMP"/blank_*.png
BLANK_TAIL=$(tail_pixels "$TMP/blank.png")
log "blank screenshot taken (grid pixels $g, tail-colour pixels $BLANK_TAIL)"
[ "$BLANK_TAIL" -lt "$MIN_TAIL_PIXELS" ] ||
  fail "blank screenshot already has $BLANK_TAIL tail-colour pixels; is the view or colour wrong?"

# ---------------------------------------------------------------------------- 3. play and check
spawn "$TMP/play.log" rosbag play --clock --loop -q "$BAG"
PLAY_PID=$LAST_PID
sleep 2
best_changed=0 best_tail=0 passed=0
deadline=$(( $(date +%s) + 30 ))
i=0
while [ "$(date +%s)" -lt "$deadline" ]; do
  rviz_alive
  kill -0 "$PLAY_PID" 2>/dev/null || { tail -n 20 "$TMP/play.log"; fail "rosbag play died"; }
  i=$((i + 1))
  shoot "$TMP/shot_$i.png" || { sleep 1; continue; }
  changed=$(changed_pixels "$TMP/blank.png" "$TMP/shot_$i.png" "$DIFF_FUZZ")
  tail=$(tail_pixels "$TMP/shot_$i.png")
  log "shot $i: changed pixels $changed (min $MIN_CHANGED_PIXELS), tail-colour pixels $tail (min $MIN_TAIL_PIXELS)"
  # keep the best screenshot (the loop of the bag jumps back in time, which resets rviz displays
  # for a moment)
  if [ "${tail:-0}" -gt "$best_tail" ] || [ ! -f "$TMP/shot.png" ]; then
    best_changed=${changed:-0} best_tail=${tail:-0}
    cp -f "$TMP/shot_$i.png" "$TMP/shot.png"
  fi
  if [ "${changed:-0}" -ge "$MIN_CHANGED_PIXELS" ] && [ "${tail:-0}" -ge "$MIN_TAIL_PIXELS" ]; then
    best_changed=$changed best_tail=$tail
    cp -f "$TMP/shot_$i.png" "$TMP/shot.png"
    passed=1
    break
  fi
  sleep 1
done
rm -f "$TMP"/shot_*.png
[ -f "$TMP/shot.png" ] || fail "could not take any screenshot"
changed_pixels "$TMP/blank.png" "$TMP/shot.png" "$DIFF_FUZZ" "$TMP/diff.png" >/dev/null
rviz_alive

log "RESULT blank->shot changed pixels: $best_changed (threshold $MIN_CHANGED_PIXELS)"
log "RESULT tail-colour pixels: blank $BLANK_TAIL, shot $best_tail (threshold $MIN_TAIL_PIXELS)"
[ "$passed" = 1 ] || fail "rods not rendered: changed $best_changed < $MIN_CHANGED_PIXELS or tail-colour $best_tail < $MIN_TAIL_PIXELS"

# ---------------------------------------------------------------------------- 4. waypoints
# A steering bag's waypoints appear once the controller has measured the start frame's course
# (about 30 s into the session): the tolerance spheres, (1.0, 0.6, 0.1) at alpha 0.25 over the
# (48,48,48) background, render near rgb(100,74,42). Shots until they are in view.
if [ "$SESSION" = steering ]; then
  best_wp=0
  deadline=$(( $(date +%s) + 75 ))
  i=0
  while [ "$(date +%s)" -lt "$deadline" ]; do
    rviz_alive
    i=$((i + 1))
    shoot "$TMP/wp_$i.png" || { sleep 1; continue; }
    wp=$(colour_pixels "$TMP/wp_$i.png" "$WAYPOINT_RGB" "$WAYPOINT_FUZZ")
    log "shot $i: waypoint-colour pixels $wp (min $MIN_WAYPOINT_PIXELS)"
    if [ "${wp:-0}" -gt "$best_wp" ]; then
      best_wp=${wp:-0}
      cp -f "$TMP/wp_$i.png" "$TMP/waypoints.png"
    fi
    [ "$best_wp" -ge "$MIN_WAYPOINT_PIXELS" ] && break
    sleep 2
  done
  rm -f "$TMP"/wp_*.png
  BLANK_WP=$(colour_pixels "$TMP/blank.png" "$WAYPOINT_RGB" "$WAYPOINT_FUZZ")
  log "RESULT waypoint-colour pixels: blank $BLANK_WP, best shot $best_wp (threshold $MIN_WAYPOINT_PIXELS)"
  [ "$best_wp" -ge "$MIN_WAYPOINT_PIXELS" ] || fail "waypoints not rendered"
fi
RESULT=0
log "PASS"
