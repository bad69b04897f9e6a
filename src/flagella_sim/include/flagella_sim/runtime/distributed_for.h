// MPI for the tools that run their simulations in-process (flagella_run sweep,
// flagella_buckling --sweep, flagella_identify): started under mpirun, the tool runs on every
// rank as one replicated program. Every rank executes the same deterministic steps;
// distributedFor splits a batch of independent tasks over the ranks (each rank its share on
// `jobs` threads of parallelFor) and gathers the results, serialized as text, on every rank, so
// every rank goes on with the same data. Only rank 0 writes outputs. Without mpirun, or when
// built without MPI, distributedFor is parallelFor.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace flagella {

/// Initialises MPI for the scope of a tool's main when it was started by mpirun (OpenMPI's
/// OMPI_COMM_WORLD_SIZE or a PMI_SIZE in the environment) with more than one rank, or always
/// with `even_alone` (flagella_sweep's mpi backend, which also runs as a single rank); finalises
/// it at the end of the scope. A no-op when built without MPI.
class MpiScope {
 public:
  explicit MpiScope(bool even_alone = false);
  ~MpiScope();
  MpiScope(const MpiScope&) = delete;
  MpiScope& operator=(const MpiScope&) = delete;
};

int mpiRank();         ///< 0 without MPI
int mpiSize();         ///< 1 without MPI
bool isRootRank();     ///< rank 0: the one that writes outputs
bool mpiCompiledIn();  ///< built with MPI

/// Runs fn(i) for i in [0, count) over the ranks (i modulo the rank count) and their `jobs`
/// threads; returns every result in index order on every rank. An exception in any task is
/// rethrown on every rank (as std::runtime_error with its message) after all tasks ran.
std::vector<std::string> distributedFor(int count, int jobs,
                                        const std::function<std::string(int)>& fn);

}  // namespace flagella
