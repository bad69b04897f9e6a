#!/usr/bin/env bash
# Set up, build, and run the whole test suite; exits non-zero on any failure and prints the
# test runner's summary.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "$FLAGELLA_ROOT/scripts/setup.sh"
bash "$FLAGELLA_ROOT/scripts/build.sh"
cd "$FLAGELLA_ROOT/build"
# ctest returns non-zero when any test fails (catkin_make run_tests alone would not).
ctest --output-on-failure -j"$(nproc)" "$@"
