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

void Identification::say(const std::string& line) const {
  if (t_held) {
    t_held->push_back({false, line});
    return;
  }
  if (options_.progress) options_.progress(line);
}

std::function<void(const std::string&)> Identification::fitProgress() const {
  if (!options_.fit.progress) return nullptr;
  return [this](const std::string& line) {
    if (t_held)
      t_held->push_back({true, line});
    else
      options_.fit.progress(line);
  };
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
  most_fits_at_once_ = std::max(most_fits_at_once_, at_once);
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
    for (const HeldLine& line : lines) {
      if (t_held)
        t_held->push_back(line);
      else if (line.from_fit && options_.fit.progress)
        options_.fit.progress(line.text);
      else if (!line.from_fit && options_.progress)
        options_.progress(line.text);
    }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace identify
}  // namespace flagella
