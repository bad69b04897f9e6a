// Tasks over MPI ranks, results gathered on every rank (distributed_for.h).
#include "flagella_sim/runtime/distributed_for.h"

#include <cstdlib>
#include <stdexcept>

#include "flagella_sim/runtime/parallel_for.h"

#ifdef FLAGELLA_WITH_MPI
#include <mpi.h>
#endif

namespace flagella {

namespace {

bool g_mpi = false;  ///< MPI initialised by an MpiScope
int g_rank = 0, g_size = 1;
const char kErrorMark = '\x01';  ///< first byte of a task's result when it threw

bool startedByMpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* v = std::getenv(var);
    if (v && std::atoi(v) > 1) return true;
  }
  return false;
}

/// The tasks of this rank on its threads, each result (or its error) as text.
std::vector<std::string> localShare(int count, int jobs, const std::function<std::string(int)>& fn,
                                    std::vector<int>& mine) {
  mine.clear();
  for (int i = g_rank; i < count; i += g_size) mine.push_back(i);
  std::vector<std::string> out(mine.size());
  parallelFor(static_cast<int>(mine.size()), jobs, [&](int k) {
    try {
      out[k] = fn(mine[k]);
    } catch (const std::exception& e) {
      out[k] = std::string(1, kErrorMark) + e.what();
    }
  });
  return out;
}

}  // namespace

#ifdef FLAGELLA_WITH_MPI

MpiScope::MpiScope(bool even_alone) {
  if (!even_alone && !startedByMpirun()) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) MPI_Init(nullptr, nullptr);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_mpi = true;
}

MpiScope::~MpiScope() {
  if (!g_mpi) return;
  MPI_Finalize();
  g_mpi = false;
  g_rank = 0;
  g_size = 1;
}

bool mpiCompiledIn() { return true; }

#else

MpiScope::MpiScope(bool) {}
MpiScope::~MpiScope() {}
bool mpiCompiledIn() { return false; }

#endif

int mpiRank() { return g_rank; }
int mpiSize() { return g_size; }
bool isRootRank() { return g_rank == 0; }

std::vector<std::string> distributedFor(int count, int jobs,
                                        const std::function<std::string(int)>& fn) {
  std::vector<int> mine;
  const std::vector<std::string> local = localShare(count, jobs, fn, mine);
  std::vector<std::string> all(static_cast<std::size_t>(std::max(0, count)));
#ifdef FLAGELLA_WITH_MPI
  if (g_mpi && g_size > 1) {
    // Every rank learns every result: lengths first, then the bytes.
    std::vector<int> lengths;
    std::string bytes;
    for (const std::string& s : local) {
      lengths.push_back(static_cast<int>(s.size()));
      bytes += s;
    }
    std::vector<int> counts(g_size), displs(g_size);
    for (int r = 0; r < g_size; ++r) counts[r] = (count - r + g_size - 1) / g_size;
    for (int r = 1; r < g_size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    std::vector<int> all_lengths(static_cast<std::size_t>(count));
    MPI_Allgatherv(lengths.data(), static_cast<int>(lengths.size()), MPI_INT, all_lengths.data(),
                   counts.data(), displs.data(), MPI_INT, MPI_COMM_WORLD);
    std::vector<int> byte_counts(g_size, 0), byte_displs(g_size, 0);
    for (int r = 0, k = 0; r < g_size; ++r)
      for (int n = 0; n < counts[r]; ++n) byte_counts[r] += all_lengths[k++];
    for (int r = 1; r < g_size; ++r) byte_displs[r] = byte_displs[r - 1] + byte_counts[r - 1];
    std::string all_bytes(static_cast<std::size_t>(byte_displs.back() + byte_counts.back()), '\0');
    MPI_Allgatherv(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, all_bytes.data(),
                   byte_counts.data(), byte_displs.data(), MPI_CHAR, MPI_COMM_WORLD);
    for (int r = 0, k = 0; r < g_size; ++r) {
      std::size_t offset = static_cast<std::size_t>(byte_displs[r]);
      for (int n = 0; n < counts[r]; ++n, ++k) {
        const int index = r + n * g_size;
        all[index] = all_bytes.substr(offset, static_cast<std::size_t>(all_lengths[k]));
        offset += static_cast<std::size_t>(all_lengths[k]);
      }
    }
  } else
#endif
  {
    for (std::size_t k = 0; k < mine.size(); ++k) all[mine[k]] = local[k];
  }
  for (const std::string& s : all)
    if (!s.empty() && s[0] == kErrorMark) throw std::runtime_error(s.substr(1));
  return all;
}

}  // namespace flagella
