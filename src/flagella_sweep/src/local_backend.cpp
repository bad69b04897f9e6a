// The local backend and the progress line (backends.h).
#include <chrono>
#include <cstdio>
#include <mutex>

#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sweep/backends.h"
#include "flagella_sweep/point_runner.h"

namespace flagella::sweep {

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void RunReport::add(const nlohmann::json& record) {
  ++ran;
  if (record["status"] != "ok") ++failed;
  point_wall += record["wall_s"].get<double>();
}

Progress::Progress(int total, int already, bool quiet)
    : total_(total), done_(already), quiet_(quiet), start_(steadySeconds()) {
  if (!quiet_ && already > 0)
    std::fprintf(stderr, "sweep: resuming, %d of %d points already done\n", already, total);
}

void Progress::pointDone(const nlohmann::json& record) {
  ++done_;
  ++ran_;
  const bool ok = record["status"] == "ok";
  if (!ok) ++failed_;
  if (quiet_) return;
  const double elapsed = steadySeconds() - start_;
  const double eta = elapsed / ran_ * (total_ - done_);
  std::fprintf(stderr, "sweep: %d/%d done (point %d %s, %.1f s)%s; elapsed %.0f s, ETA %.0f s\n",
               done_, total_, record["index"].get<int>(), ok ? "ok" : "FAILED",
               record["wall_s"].get<double>(),
               failed_ ? (", " + std::to_string(failed_) + " failed").c_str() : "", elapsed, eta);
  if (!ok)
    std::fprintf(stderr, "sweep: point %d: %s\n", record["index"].get<int>(),
                 record["error"].get<std::string>().c_str());
}

RunReport runLocal(const SweepSpec& spec, const SweepStore& store, int jobs, bool quiet) {
  RunReport report;
  report.total = static_cast<int>(spec.points.size());
  const std::vector<int> todo = store.missing(report.total);
  report.already = report.total - static_cast<int>(todo.size());
  report.workers = std::min<int>(jobs, std::max<std::size_t>(1, todo.size()));
  Progress progress(report.total, report.already, quiet);
  const std::string tools = executableDirectory();
  std::mutex mutex;
  const double start = steadySeconds();
  parallelFor(static_cast<int>(todo.size()), jobs, [&](int k) {
    const nlohmann::json record = runPoint(spec, todo[k], tools, store.workDirectory(todo[k]));
    store.writeRecord(record);
    std::lock_guard<std::mutex> lock(mutex);
    report.add(record);
    progress.pointDone(record);
  });
  report.wall = steadySeconds() - start;
  return report;
}

}  // namespace flagella::sweep
