// The one in-process worker pool of the project's tools (sweeps, identification's model runs,
// buckling sweeps, robustness runs): a bounded number of threads that take indices in order.
// flagella_sweep's local backend runs its point processes on it too.
#pragma once

#include <functional>
#include <string>

namespace flagella {

/// Largest worker count any tool accepts.
constexpr int kMaxJobs = 256;

/// The machine's core count (at least 1): the default `--jobs`.
int defaultJobs();

/// Throws ConfigError "<field> must be in [1, 256], got <jobs>" unless 1 <= jobs <= kMaxJobs.
void requireJobs(const std::string& field, int jobs);

/// Runs fn(i) for every i in [0, count) on min(jobs, count) threads (the calling thread when
/// that is 1), indices taken in increasing order. Every index runs even if another throws; the
/// first exception (by index) is rethrown after all have finished. `jobs` must be >= 1.
void parallelFor(int count, int jobs, const std::function<void(int)>& fn);

}  // namespace flagella
