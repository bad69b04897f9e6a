# Sourced by the other scripts: the system python must come first (a pyenv python3 on PATH
# lacks catkin_pkg; see docs/ros-notes in the README), and the workspace root is exported.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
FLAGELLA_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export FLAGELLA_ROOT
# One BLAS thread: a process then starts no OpenBLAS worker thread (which otherwise spins on
# sched_yield for about 0.1 s of CPU at start-up, taken from the other job on two cores). The
# tools parallelise across simulations, never inside a dense solve.
export OPENBLAS_NUM_THREADS=1
