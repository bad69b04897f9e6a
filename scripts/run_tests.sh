#!/usr/bin/env bash
# Set up, build, and run the whole test suite; exits non-zero on any failure and prints the
# test runner's summary. Arguments are passed to ctest, e.g. -R test_strict_yaml; --help.
set -euo pipefail
usage() {
  cat <<USAGE
Usage: bash scripts/run_tests.sh [CTEST OPTION ...]
Sets up and builds the workspace, then runs the test suite with ctest (all tests, in parallel
over the cores). Options are passed to ctest, for example:
  -R REGEX   only the tests whose name matches     -E REGEX   all but those
  -j N       N tests at a time                     --repeat until-fail:N, --timeout S, -V
A selection that matches no test is an error.
USAGE
}
# ctest options that take a value (the next argument); anything else must itself be an option.
takes_value=" -R -E -L -LE -j -I -C -O --tests-regex --exclude-regex --label-regex
  --label-exclude --parallel --timeout --repeat --stop-time --output-log --test-load "
expect_value=""
for arg in "$@"; do
  if [[ -n "$expect_value" ]]; then
    expect_value=""
    continue
  fi
  case "$arg" in
    -h | --help) usage; exit 0 ;;
    -*) [[ "$takes_value" == *" $arg "* ]] && expect_value="$arg" ;;
    *)
      echo "run_tests: unexpected argument '$arg' (pass ctest options, e.g. -R REGEX; --help)" >&2
      exit 2
      ;;
  esac
done
if [[ -n "$expect_value" ]]; then
  echo "run_tests: option $expect_value needs a value (--help)" >&2
  exit 2
fi
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "$FLAGELLA_ROOT/scripts/setup.sh"
bash "$FLAGELLA_ROOT/scripts/build.sh"
cd "$FLAGELLA_ROOT/build"
# rostest's masters and nodes on loopback only, their logs in a temporary ROS_HOME.
export ROS_HOSTNAME=localhost
ROS_HOME="$(mktemp -d)"
export ROS_HOME
trap 'rm -rf "$ROS_HOME"' EXIT
# ctest returns non-zero when any test fails (catkin_make run_tests alone would not), and with
# --no-tests=error when a selection matches none.
ctest --output-on-failure --no-tests=error -j"$(nproc)" "$@"
