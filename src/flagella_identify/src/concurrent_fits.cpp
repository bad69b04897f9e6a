// Independent fits run two at a time, their progress said in order (docs/model.md 7.6).
#include <algorithm>
#include <exception>
#include <utility>

#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "identify_internal.h"

namespace flagella {
namespace identify {

namespace {

/// A progress line held while its fit runs beside another: from say() or from a fit's own
/// progress (FitOptions::progress).
struct HeldLine {
  bool from_fit = false;
  std::string text;
};

/// The lines of the fit this thread runs, when fits run concurrently; null otherwise.
thread_local std::vector<HeldLine>* t_held = nullptr;

/// Holds this thread's progress lines in `lines` while it lives.
class HoldProgress {
 public:
  explicit HoldProgress(std::vector<HeldLine>& lines) : previous_(t_held) { t_held = &lines; }
  ~HoldProgress() { t_held = previous_; }
  HoldProgress(const HoldProgress&) = delete;
  HoldProgress& operator=(const HoldProgress&) = delete;

 private:
  std::vector<HeldLine>* previous_;
};

}  // namespace

void Identification::emit(bool from_fit, const std::string& line) const {
  if (t_held) {
    t_held->push_back({from_fit, line});
    return;
  }
  const std::function<void(const std::string&)>& sink =
      from_fit ? options_.fit.progress : options_.progress;
  if (sink) sink(line);
}

void Identification::say(const std::string& line) const { emit(false, line); }

std::function<void(const std::string&)> Identification::fitProgress() const {
  if (!options_.fit.progress) return nullptr;
  return [this](const std::string& line) { emit(true, line); };
}

int Identification::fitsAtOnce(int count) const {
  // Under mpirun every rank runs the same fits in the same order (distributed_for.h): one at a
  // time there. Two at once fill a core that one fit leaves idle; more would only interleave.
  if (!options_.concurrent_fits || mpiSize() > 1 || options_.evaluator.jobs < 2) return 1;
  return count < 2 ? 1 : 2;
}

void Identification::runFits(const std::vector<std::function<void()>>& fits) {
  const int at_once = fitsAtOnce(static_cast<int>(fits.size()));
  if (at_once == 1) {
    for (const std::function<void()>& fit : fits) fit();
    return;
  }
  // Recorded by the outermost batch only: a nested one runs on a thread of a concurrent batch,
  // which has recorded already, and two threads must not write it.
  if (!t_held) most_fits_at_once_ = std::max(most_fits_at_once_, at_once);
  // docs/model.md 7.6: each fit is the same computation as when run alone (its model runs are
  // deterministic whatever the threads); only the wall time and the order of work change.
  std::vector<std::vector<HeldLine>> held(fits.size());
  std::exception_ptr failure;
  try {
    parallelFor(static_cast<int>(fits.size()), at_once, [&](int i) {
      HoldProgress hold(held[static_cast<size_t>(i)]);
      fits[static_cast<size_t>(i)]();
    });
  } catch (...) {
    failure = std::current_exception();
  }
  // In order; into the enclosing fit's lines when these fits ran inside one.
  for (const std::vector<HeldLine>& lines : held)
    for (const HeldLine& line : lines) emit(line.from_fit, line.text);
  if (failure) std::rethrow_exception(failure);
}

}  // namespace identify
}  // namespace flagella
