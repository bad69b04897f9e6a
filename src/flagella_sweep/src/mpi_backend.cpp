// The MPI backend (backends.h): rank 0 hands out point indices one at a time and stores the
// records the workers send back as JSON text.
#include <chrono>
#include <stdexcept>
#include <thread>

#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sweep/backends.h"
#include "flagella_sweep/point_runner.h"

#ifdef FLAGELLA_WITH_MPI
#include <mpi.h>
#endif

namespace flagella::sweep {

#ifndef FLAGELLA_WITH_MPI

RunReport runMpi(const SweepSpec&, const SweepStore&, bool, int&) {
  // flagella_sweep refuses --backend mpi before this when built without MPI.
  throw std::runtime_error("built without MPI");
}

#else

namespace {

enum Tag { kReady = 1, kWork = 2, kStop = 3 };

/// Receives a text message from any rank; returns the sender. Polls with a short sleep instead
/// of a blocking probe: OpenMPI's blocking calls spin, and a spinning rank 0 would take a core
/// from the workers when ranks share cores (mpirun --oversubscribe, or rank 0 beside workers).
int receiveText(std::string& text, int& tag) {
  MPI_Status status;
  for (int arrived = 0;;) {
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  int size = 0;
  MPI_Get_count(&status, MPI_CHAR, &size);
  text.assign(static_cast<std::size_t>(size), '\0');
  MPI_Recv(text.data(), size, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  tag = status.MPI_TAG;
  return status.MPI_SOURCE;
}

void sendText(const std::string& text, int to, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

}  // namespace

RunReport runMpi(const SweepSpec& spec, const SweepStore& store, bool quiet, int& rank) {
  const MpiScope mpi(true);
  rank = mpiRank();
  const int size = mpiSize();
  RunReport report;
  const std::string tools = executableDirectory();
  if (rank != 0) {  // worker: ask, run, answer with the record, until told to stop
    sendText("", 0, kReady);
    for (;;) {
      std::string text;
      int tag = 0;
      receiveText(text, tag);
      if (tag == kStop) break;
      const int index = std::stoi(text);
      sendText(runPoint(spec, index, tools, store.workDirectory(index)).dump(), 0, kReady);
    }
    return report;
  }
  report.total = static_cast<int>(spec.points.size());
  const std::vector<int> todo = store.missing(report.total);
  report.already = report.total - static_cast<int>(todo.size());
  report.workers = size > 1 ? size - 1 : 1;
  Progress progress(report.total, report.already, quiet);
  const double start = steadySeconds();
  auto store_record = [&](const nlohmann::json& record) {
    store.writeRecord(record);
    report.add(record);
    progress.pointDone(record);
  };
  std::size_t next = 0;
  if (size == 1) {
    for (int index : todo) store_record(runPoint(spec, index, tools, store.workDirectory(index)));
  } else {
    int active = size - 1;
    while (active > 0) {
      std::string text;
      int tag = 0;
      const int from = receiveText(text, tag);
      if (!text.empty()) store_record(nlohmann::json::parse(text));
      if (next < todo.size()) {
        sendText(std::to_string(todo[next++]), from, kWork);
      } else {
        sendText("", from, kStop);
        --active;
      }
    }
  }
  report.wall = steadySeconds() - start;
  return report;
}

#endif

}  // namespace flagella::sweep
