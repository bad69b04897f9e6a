// Bounded worker pool of the tools (parallel_for.h).
#include "flagella_sim/runtime/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

int defaultJobs() {
  return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, kMaxJobs);
}

void requireJobs(const std::string& field, int jobs) {
  if (jobs < 1 || jobs > kMaxJobs)
    throw ConfigError(field + " must be in [1, " + std::to_string(kMaxJobs) + "], got " +
                      std::to_string(jobs));
}

void parallelFor(int count, int jobs, const std::function<void(int)>& fn) {
  if (count <= 0) return;
  std::vector<std::exception_ptr> errors(count);
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int i = next++; i < count; i = next++) {
      try {
        fn(i);
      } catch (...) {  // never let an exception escape a worker thread
        errors[i] = std::current_exception();
      }
    }
  };
  const int threads = std::clamp(jobs, 1, count);
  if (threads == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace flagella
