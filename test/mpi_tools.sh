#!/usr/bin/env bash
# The tools that run their simulations in-process, under mpirun (distributed_for.h): each gives
# the same result with its runs spread over 2-3 ranks as in one process: flagella_run sweep
# (sweep.csv identical), flagella_buckling --sweep (buckling_sweep.csv identical) and
# flagella_identify --calibrate-only (calibration.json identical but for its own path); the
# ranks other than 0 leave no files behind.
# Usage: mpi_tools.sh DEVEL_BIN
set -euo pipefail
bin=$1
source "$(dirname "${BASH_SOURCE[0]}")/scratch_dir.sh"
mpi() { timeout 300 mpirun --allow-run-as-root --oversubscribe -np "$@"; }

sweep=(sweep "$root/config/helical_robot.yaml" --omega-rpm 5,10,15,20 --duration 0.5 --jobs 1 --plot-script '' --quiet)
"$bin/flagella_run" "${sweep[@]}" --out run1 > /dev/null
mpi 2 "$bin/flagella_run" "${sweep[@]}" --out run2 > /dev/null
diff run1/sweep.csv run2/sweep.csv || fail "flagella_run sweep differs under mpirun -np 2"
[ "$(wc -l < run1/sweep.csv)" -eq 5 ] || fail "expected 4 rows"

buckling=("$root/config/helical_gimbal.yaml" --set robot.edge_length=0.015
  --sweep robot.filament_radius=1.2e-3,1.584e-3,2e-3 --low 2 --high 12 --rel-tolerance 0.3
  --observe-turns 5 --settle-turns 2 --max-runs 5 --jobs 1 --plot-script '' --quiet)
"$bin/flagella_buckling" "${buckling[@]}" --out buck1 > /dev/null || true  # exit 3: one not found
mpi 3 "$bin/flagella_buckling" "${buckling[@]}" --out buck3 > /dev/null 2>&1 || true
diff buck1/buckling_sweep.csv buck3/buckling_sweep.csv || fail "flagella_buckling --sweep differs under mpirun -np 3"
grep -q ',1,' buck1/buckling_sweep.csv || fail "no threshold found at all"

before=$(ls /tmp | grep -c '^flagella_identify_rank' || true)
identify=(--data "$root/data/examples/design1_yield_table.yaml"
  --config "$root/config/identification/granular_design1_coarse.yaml" --calibrate-only
  --free medium.viscosity --no-plot --quiet --jobs 1)
"$bin/flagella_identify" "${identify[@]}" --out id1 > /dev/null
mpi 2 "$bin/flagella_identify" "${identify[@]}" --out id2 > /dev/null
diff <(sed 's#id[12]/#idN/#' id1/calibration.json | grep -v wall) \
  <(sed 's#id[12]/#idN/#' id2/calibration.json | grep -v wall) ||
  fail "flagella_identify --calibrate-only differs under mpirun -np 2"
after=$(ls /tmp | grep -c '^flagella_identify_rank' || true)
[ "$after" -eq "$before" ] || fail "a rank left its scratch folder in /tmp"
echo "mpi tools: flagella_run sweep, flagella_buckling --sweep and flagella_identify give the same results under mpirun"
