// Where a sweep's points run. Every backend runs only the points without a record, stores each
// record as it arrives (SweepStore), and leaves the table to SweepStore::writeTable, so the
// table does not depend on the backend or the order in which points finished.
//  - local: a pool of `jobs` worker threads, each running one point process at a time;
//  - mpi: under mpirun, rank 0 hands out points one at a time and stores the records the other
//    ranks send back (with one rank, rank 0 runs them itself);
//  - slurm: an sbatch array script whose task i runs `flagella_sweep run-point ... --index i`;
//    `flagella_sweep collect` builds the table afterwards.
#pragma once

#include <string>
#include <vector>

#include "flagella_sweep/sweep_spec.h"
#include "flagella_sweep/sweep_store.h"

namespace flagella::sweep {

struct RunReport {
  int total = 0;            ///< points in the sweep
  int already = 0;          ///< records present before this run
  int ran = 0;              ///< points run now
  int failed = 0;           ///< of those, failed
  double wall = 0.0;        ///< this run's wall time [s]
  double point_wall = 0.0;  ///< sum of the points' own wall times [s]
  int workers = 1;
  /// Counts a point's record (ran, failed, point_wall).
  void add(const nlohmann::json& record);
};

/// Progress line per finished point on stderr (done/total, failures, ETA) unless quiet.
/// Seconds of the steady clock.
double steadySeconds();

class Progress {
 public:
  Progress(int total, int already, bool quiet);
  void pointDone(const nlohmann::json& record);

 private:
  int total_, done_, failed_ = 0, ran_ = 0;
  bool quiet_;
  double start_;
};

RunReport runLocal(const SweepSpec& spec, const SweepStore& store, int jobs, bool quiet);

/// Runs under MPI (MpiScope of distributed_for.h inside; flagella::mpiCompiledIn tells whether
/// this build has MPI). Returns the report on rank 0; on the other
/// ranks `rank` is set > 0 and the report is empty.
RunReport runMpi(const SweepSpec& spec, const SweepStore& store, bool quiet, int& rank);

/// Writes OUT/sweep.sbatch (an array over the missing points) and returns its path. `sweep_path`
/// and the store's folder are written as absolute paths; `extra_sbatch` lines go in verbatim
/// (e.g. "--time=01:00:00").
std::string writeSlurmScript(const SweepSpec& spec, const SweepStore& store,
                             const std::vector<std::string>& extra_sbatch, int max_running);
/// "0-3,7,9-10": a sorted index list in Slurm's --array syntax.
std::string arrayRanges(const std::vector<int>& indices);

}  // namespace flagella::sweep
