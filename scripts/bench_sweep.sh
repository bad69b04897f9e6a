#!/usr/bin/env bash
# Benchmark of flagella_sweep's runner (README "Sweeps"): the same sweep of short helical runs
# (POINTS points of 1 s simulated, about 0.5 s each) run four ways:
#   - the bare tool commands one after the other in a bash loop (no runner at all);
#   - local --jobs 1: the runner's overhead per point = (its wall time - the loop's) / POINTS;
#   - local --jobs 2 and mpirun -np 3 (two workers): parallel efficiency = T(jobs 1) / (2 T).
# Run it on a quiet machine (nothing else on either core).
# Usage: bash scripts/bench_sweep.sh [POINTS]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$root/devel/bin
points=${1:-16}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
config=$root/config/helical_robot.yaml
rates=$(/usr/bin/python3 -c "print(' '.join(str(4 + i) for i in range($points)))")
cat > "$work/bench.yaml" <<YAML
sweep:
  tool: run
  config: $config
  grid:
    motor.omega_rpm: [${rates// /, }]
    simulation.duration: [1]
YAML
now() { date +%s.%N; }
t0=$(now)
for r in $rates; do
  "$bin/flagella_run" run "$config" --out "$work/loop" --quiet --set "motor.omega_rpm=$r" \
    --set simulation.duration=1 > /dev/null
done
t1=$(now)
"$bin/flagella_sweep" run "$work/bench.yaml" --out "$work/j1" --jobs 1 --quiet > /dev/null
t2=$(now)
"$bin/flagella_sweep" run "$work/bench.yaml" --out "$work/j2" --jobs 2 --quiet > /dev/null
t3=$(now)
mpirun --allow-run-as-root --oversubscribe -np 3 "$bin/flagella_sweep" run "$work/bench.yaml" \
  --backend mpi --out "$work/mpi" --quiet > /dev/null
t4=$(now)
# MPI's own start-up and shut-down: the same command with every point already done.
mpirun --allow-run-as-root --oversubscribe -np 3 "$bin/flagella_sweep" run "$work/bench.yaml" \
  --backend mpi --out "$work/mpi" --quiet > /dev/null
t5=$(now)
/usr/bin/python3 - "$points" "$t0" "$t1" "$t2" "$t3" "$t4" "$t5" <<'PY'
import sys
n = int(sys.argv[1]); t = [float(x) for x in sys.argv[2:]]
loop, j1, j2, mpi, start = t[1] - t[0], t[2] - t[1], t[3] - t[2], t[4] - t[3], t[5] - t[4]
print(f"sweep benchmark, {n} points of 1 s simulated (helical robot)")
print(f"  bare tool loop      {loop:7.2f} s ({loop / n:.3f} s per point)")
print(f"  local --jobs 1      {j1:7.2f} s: runner overhead {1e3 * (j1 - loop) / n:.1f} ms per point")
print(f"  local --jobs 2      {j2:7.2f} s: speed-up {j1 / j2:.2f}, parallel efficiency {100 * j1 / (2 * j2):.1f} %")
print(f"  mpirun -np 3        {mpi:7.2f} s: speed-up {j1 / mpi:.2f}, parallel efficiency {100 * j1 / (2 * mpi):.1f} % (2 workers)")
print(f"  mpirun start-up     {start:7.2f} s (nothing left to run); without it: efficiency {100 * j1 / (2 * (mpi - start)):.1f} %")
PY
