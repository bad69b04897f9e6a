#!/usr/bin/env bash
# flagella_sweep's backends against each other on a real sweep of short helical runs: local
# --jobs 1, local --jobs 2, mpirun -np 3 and the Slurm array's tasks run by hand must give the
# same table (timing columns aside: the runner's wall_s and the tool's wall_time_s and
# real_time_factor); a sweep killed mid-way resumes with only the missing points and ends with
# the same table; a failing point is recorded with its error while the others finish (exit 3);
# a bad sweep file fails before anything runs (exit 2, the field named, no folder written).
# Usage: sweep_backends.sh DEVEL_BIN
set -euo pipefail
bin=$1
source "$(dirname "${BASH_SOURCE[0]}")/scratch_dir.sh"

cat > sweep.yaml <<YAML
sweep:
  tool: run
  config: $root/config/helical_robot.yaml
  grid:
    motor.omega_rpm: [4, 8, 12, 16, 20, 24]
    simulation.duration: [0.4]
YAML
# The table without its timing columns.
strip() {
  /usr/bin/python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, c in enumerate(rows[0]) if c not in ("wall_s", "wall_time_s", "real_time_factor")]
for r in rows:
    print(",".join(r[i] for i in keep))
PY
}

"$bin/flagella_sweep" run sweep.yaml --out local1 --jobs 1 --quiet
strip local1/results.csv > ref.csv
[ "$(wc -l < ref.csv)" -eq 7 ] || fail "expected 6 rows, got: $(cat ref.csv)"
grep -q ',ok,0,,' ref.csv || fail "no ok rows"

"$bin/flagella_sweep" run sweep.yaml --out local2 --jobs 2 --quiet
strip local2/results.csv | diff ref.csv - || fail "local --jobs 2 differs from --jobs 1"

timeout 300 mpirun --allow-run-as-root --oversubscribe -np 3 "$bin/flagella_sweep" run sweep.yaml \
  --backend mpi --out mpi3 --quiet
strip mpi3/results.csv | diff ref.csv - || fail "mpirun -np 3 differs from local --jobs 1"

"$bin/flagella_sweep" run sweep.yaml --backend slurm --out slurm > slurm.txt
script=slurm/sweep.sbatch
bash -n "$script" || fail "the sbatch script is not valid bash"
grep -q '^#SBATCH --array=0-5$' "$script" || fail "array line: $(grep array "$script")"
for i in 0 1 2 3 4 5; do SLURM_ARRAY_TASK_ID=$i bash "$script" > /dev/null; done
"$bin/flagella_sweep" collect sweep.yaml --out slurm > /dev/null
strip slurm/results.csv | diff ref.csv - || fail "Slurm tasks + collect differ from local"

# Kill mid-way (SIGKILL: no chance to clean up), then resume.
"$bin/flagella_sweep" run sweep.yaml --out killed --jobs 1 --quiet &
pid=$!
for _ in $(seq 1 200); do
  [ "$(ls killed/points 2>/dev/null | grep -c '\.json$')" -ge 2 ] && break
  sleep 0.05
done
kill -9 "$pid"
wait "$pid" 2>/dev/null || true
done_before=$(ls killed/points | grep -c '\.json$')
[ "$done_before" -ge 2 ] && [ "$done_before" -lt 6 ] || fail "kill came at $done_before of 6 points"
"$bin/flagella_sweep" run sweep.yaml --out killed --jobs 2 > resumed.txt 2> resumed.err
grep -q "resuming, $done_before of 6 points already done" resumed.err || fail "no resume line: $(cat resumed.err)"
grep -q "ran $((6 - done_before)) points" resumed.txt || fail "resume ran the wrong count: $(cat resumed.txt)"
strip killed/results.csv | diff ref.csv - || fail "resumed table differs"

# A failing point (a tolerance Newton cannot meet) is recorded; the others finish.
cat > failing.yaml <<YAML
sweep:
  tool: run
  config: $root/config/helical_robot.yaml
  points:
    - {motor.omega_rpm: 8, simulation.duration: 0.3}
    - {motor.omega_rpm: 8, simulation.duration: 0.3, solver.residual_tolerance: 1e-10, solver.max_iterations: 1}
    - {motor.omega_rpm: 12, simulation.duration: 0.3}
YAML
set +e
"$bin/flagella_sweep" run failing.yaml --out failing --jobs 2 --quiet > failing.txt 2> failing.err
code=$?
set -e
[ "$code" -eq 3 ] || fail "a failing point should exit 3, got $code"
grep -q "failed point 1: exit 3: .*Newton did not converge" failing.err || fail "$(cat failing.err)"
[ "$(grep -c ',ok,0,,' failing/results.csv)" -eq 2 ] || fail "the other points did not finish"

# A bad sweep file: exit 2, the field named, nothing written.
sed 's/20, 24]/20, fast]/' sweep.yaml > bad.yaml
set +e
"$bin/flagella_sweep" run bad.yaml --out bad 2> bad.err
code=$?
set -e
[ "$code" -eq 2 ] || fail "bad sweep file should exit 2, got $code"
grep -q "point 5.*motor.omega_rpm" bad.err || fail "error does not name the point and field: $(cat bad.err)"
[ ! -e bad ] || fail "a rejected sweep wrote its folder"
echo "sweep backends: local 1 = local 2 = mpirun -np 3 = Slurm tasks = killed+resumed ($done_before of 6 before the kill); failing point recorded; bad file rejected"
