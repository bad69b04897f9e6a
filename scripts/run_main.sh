#!/usr/bin/env bash
# The main job: set up, build, and run the headless simulation of granular design 1 (n = 2,
# omega_T = 100 rpm, 200 s); prints omega_h, omega_t and v, writes out/main/.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
bash "$FLAGELLA_ROOT/scripts/setup.sh"
bash "$FLAGELLA_ROOT/scripts/build.sh"
cd "$FLAGELLA_ROOT"
./devel/bin/flagella_run run config/granular_design1.yaml --n-tails 2 --omega-rpm 100 --duration 200 --out out/main "$@"
