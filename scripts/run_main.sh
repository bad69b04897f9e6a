#!/usr/bin/env bash
# The main job: set up, build, and run a headless ROS session in which the interface robot
# follows a square with the receding-horizon path follower (launch/path_following.launch, IMU and
# camera noise, lockstep), records a bag, plots the reference and the actual head path and prints
# the cross-track error beside the path's tracking bound (flagella_tracking_bound).
# Outputs in out/main/: path_following.bag, path_following.png, summary.json, replaced only when
# the whole run succeeds (a failed or refused run leaves the previous ones as they were).
# Extra roslaunch arguments NAME:=VALUE are passed on, e.g. mode:=open_loop or
# overrides:=effects.interface_lateral_force.C_yr=1.4; --help lists them.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
LAUNCH="$ROOT/launch/path_following.launch"
OUT="$ROOT/out/main"

# The launch file's own arguments (top-level <arg ... default=... doc=...>), as "name|doc".
launch_args() {
  sed -n 's/^  <arg name="\([^"]*\)" default="[^"]*" doc="\([^"]*\)".*/\1|\2/p' "$LAUNCH"
}
usage() {
  cat <<USAGE
Usage: bash scripts/run_main.sh [NAME:=VALUE ...]
Sets up and builds the workspace, runs launch/path_following.launch headless with a recorded bag,
plots the paths and prints the cross-track error beside the tracking bound. Outputs in out/main/ (bag, plot, summary.json),
replaced only when the run succeeds.
Arguments of the launch file (record and bag are set by this script):
USAGE
  launch_args | while IFS='|' read -r name doc; do
    case "$name" in record | bag) continue ;; esac
    printf '  %-26s %s\n' "$name:=" "$doc"
  done
}

# Every argument is checked before anything is built, run or removed.
known="$(launch_args | cut -d'|' -f1)"
for arg in "$@"; do
  case "$arg" in
    -h | --help) usage; exit 0 ;;
  esac
  if [[ ! "$arg" =~ ^([A-Za-z_][A-Za-z0-9_]*):=(.*)$ ]]; then
    echo "run_main: '$arg' is not NAME:=VALUE (bash scripts/run_main.sh --help lists the names)" >&2
    exit 2
  fi
  name="${BASH_REMATCH[1]}"
  if ! grep -qx "$name" <<<"$known"; then
    echo "run_main: unknown argument '$name' (bash scripts/run_main.sh --help lists the names)" >&2
    exit 2
  fi
  if [[ "$name" == record || "$name" == bag ]]; then
    echo "run_main: '$name' is set by this script (the bag goes to $OUT)" >&2
    exit 2
  fi
done

bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/build.sh"
source "$ROOT/scripts/ros_env.sh" "$ROOT/devel/setup.bash"
mkdir -p "$ROOT/out"
STAGE="$(mktemp -d "$ROOT/out/.main.XXXXXX")"  # this run's outputs until it has succeeded
trap 'rm -rf "$STAGE"' EXIT
echo "run_main: master on $ROS_MASTER_URI; bag, plot and summary in $OUT"
if ! /usr/bin/python3 "$ROOT/scripts/roslaunch_session.py" "$LAUNCH" record:=true \
  bag:="$STAGE/path_following.bag" "$@"; then
  echo "run_main: the session failed (see its output above; logs in $ROS_HOME/log); $OUT unchanged" >&2
  exit 1
fi
if [[ ! -s "$STAGE/path_following.bag" ]]; then
  echo "run_main: the session left no bag (see the roslaunch output above); $OUT unchanged" >&2
  exit 1
fi
# The tracking bound of the path on the calibration the controller used (docs/model.md 7.5).
calibration="$ROOT/config/calibration/interface_path_planning.yaml"
path="$ROOT/config/paths/square.yaml"
for arg in "$@"; do
  case "$arg" in
    calibration:=*) calibration="${arg#calibration:=}" ;;
    path:=*) path="${arg#path:=}" ;;
  esac
done
bound_args=()
if [[ -z "$path" ]]; then
  echo "run_main: no path file (the path came on the 'path' topic): no tracking bound"
elif "$ROOT/devel/bin/flagella_tracking_bound" --calibration "$calibration" --path "$path" \
  --json "$STAGE/bound.json"; then
  bound_args=(--bound "$STAGE/bound.json")
else
  echo "run_main: the tracking bound failed (see above); the summary goes without it" >&2
fi
if ! /usr/bin/python3 "$ROOT/scripts/plot_path_following.py" "$STAGE/path_following.bag" \
  --out "$STAGE/path_following.png" --summary "$STAGE/summary.json" \
  --shown-as "$OUT/path_following.png" "${bound_args[@]}"; then
  echo "run_main: plotting the session failed; $OUT unchanged" >&2
  exit 1
fi
mkdir -p "$OUT"
for f in path_following.bag path_following.png summary.json; do
  mv -f "$STAGE/$f" "$OUT/$f"
done
