#!/usr/bin/env bash
# Every command-line tool in devel/bin shares one argument and error handling
# (flagella_sim/runtime/tool_main.h): --help prints the usage and exits 0, an unknown argument
# exits 2 with a message naming it (CLI11's own codes were 105-113), and a config that does not
# exist exits 2 naming the file, never an abort ("terminate called ...", exit 134).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scratch_dir.sh"
bin="$root/devel/bin"
count=0
for tool in "$bin"/flagella_*; do
  name=$(basename "$tool")
  status=0
  out=$("$tool" --help 2>&1) || status=$?
  [[ $status -eq 0 ]] || fail "$name --help exited $status"
  [[ "$out" == *"Usage"* || "$out" == *"usage"* ]] || fail "$name --help printed no usage"
  status=0
  out=$("$tool" --xyzzy 2>&1) || status=$?
  [[ $status -eq 2 ]] || fail "$name --xyzzy exited $status (expected 2): $out"
  [[ "$out" == *"--help for the usage"* ]] || fail "$name --xyzzy: message without the hint: $out"
  [[ "$out" != *"terminate called"* ]] || fail "$name --xyzzy aborted: $out"
  count=$((count + 1))
done
[[ $count -ge 15 ]] || fail "only $count tools found in $bin"
# A missing config: exit 2 naming the file (the tools that take a config as first argument).
for cmd in "flagella_run run" "flagella_buckling" "flagella_follow_path" "flagella_lcm_harness"; do
  status=0
  out=$("$bin"/$cmd "$work/none.yaml" 2>&1) || status=$?
  [[ $status -eq 2 ]] || fail "$cmd none.yaml exited $status (expected 2): $out"
  [[ "$out" == *"none.yaml"* ]] || fail "$cmd none.yaml: message does not name the file: $out"
done
echo "tool_arguments: $count tools: --help 0, unknown argument 2, missing config 2"
# Bad input names the input that is wrong and exits 2 (README "Exit codes"; issue reproductions).
expect_bad_input() {  # expect_bad_input WORDING COMMAND...
  local wording=$1 status=0 out
  shift
  out=$("$@" 2>&1) || status=$?
  [[ $status -eq 2 ]] || fail "$* exited $status (expected 2): $out"
  [[ "$out" == *"$wording"* ]] || fail "$*: message does not say '$wording': $out"
}
cfg="$root/config"
steer=("$bin/flagella_steer" --calibration "$cfg/calibration/helical_steering.yaml")
expect_bad_input "needs a robot with a slider" "${steer[@]}" --config "$cfg/helical_robot.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml"
expect_bad_input "square.yaml" "${steer[@]}" --config "$cfg/helical_steering.yaml" \
  --waypoints "$cfg/paths/square.yaml"
expect_bad_input "needs a robot with a slider" "$bin/flagella_steer_robustness" \
  --calibration "$cfg/calibration/helical_steering.yaml" --config "$cfg/helical_robot.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml"
# A mission set names the waypoint file it cannot read, before any run.
expect_bad_input "none_mission.yaml" "$bin/flagella_steer_robustness" \
  --calibration "$cfg/calibration/helical_steering.yaml" --config "$cfg/helical_steering.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml" "$work/none_mission.yaml"
expect_bad_input "square.yaml" "$bin/flagella_steer_robustness" \
  --calibration "$cfg/calibration/helical_steering.yaml" --config "$cfg/helical_steering.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml" "$cfg/paths/square.yaml" --runs 1
# A model-error key the config lacks fails before the reference run (which takes minutes).
expect_bad_input "model error 'k_t'" "$bin/flagella_steer_robustness" \
  --calibration "$cfg/calibration/helical_steering.yaml" --config "$cfg/helical_steering.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml" --keys eps k_t --runs 1
# A robot without a slider cannot be calibrated for steering: bad input, before any run.
expect_bad_input "the config has no slider: section" "$bin/flagella_steer_calibrate" \
  "$cfg/helical_robot.yaml" -o "$work/cal.yaml"
# A park position outside the slider's travel fails before the calibration's minutes of runs.
expect_bad_input "slider: the park position" "$bin/flagella_steer_calibrate" \
  "$cfg/helical_steering.yaml" -o "$work/cal.yaml" --set effects.com_offset.offset=5e-3
expect_bad_input "missing top-level 'path'" "$bin/flagella_follow_path" \
  "$cfg/interface_path_planning.yaml" --path "$cfg/paths/steering_demo.yaml" \
  --calibration "$cfg/calibration/interface_path_planning.yaml"
run=("$bin/flagella_run" run "$cfg/helical_robot.yaml" --duration 0.05 --out "$work/bad")
expect_bad_input "override 'robot.filament_radus=1e-3'" "${run[@]}" --set robot.filament_radus=1e-3
expect_bad_input "override 'robot.filament_radius=0.02'" "${run[@]}" --set robot.filament_radius=0.02
# The gains a user may set, with default, unit and meaning: one line per name --gain knows.
gains=$("$bin/flagella_steer" --list-gains) || fail "flagella_steer --list-gains exited non-zero"
for name in max_steer_offset turn_threshold steer_by_offset sensor_fault_timeout; do
  [[ "$gains" == *"$name "* ]] || fail "--list-gains does not list $name: $gains"
done
status=0
out=$("$bin/flagella_steer" --gain max_steer_offsett=1e-5 --config "$cfg/helical_steering.yaml" \
  --waypoints "$cfg/paths/steering_demo.yaml" --calibration "$cfg/calibration/helical_steering.yaml" \
  2>&1) || status=$?
[[ $status -eq 2 && "$out" == *"unknown gain 'max_steer_offsett'"* ]] ||
  fail "a misspelt --gain exited $status: $out"
cat >"$work/bad_point.yaml" <<YAML
sweep:
  tool: run
  config: $cfg/helical_robot.yaml
  grid:
    robot.filament_radius: [1.0e-3, 0.02]
YAML
expect_bad_input "point 1: override 'robot.filament_radius=0.02'" "$bin/flagella_sweep" run \
  "$work/bad_point.yaml" --out "$work/bad_sweep"
echo "tool_arguments: bad steering inputs, overrides and sweep points exit 2 naming the input"
