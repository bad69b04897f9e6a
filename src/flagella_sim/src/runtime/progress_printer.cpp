#include "flagella_sim/runtime/progress_printer.h"

#include <algorithm>
#include <cstdio>

namespace flagella {

namespace {
constexpr double kProgressPeriodSeconds = 2.0;
}

ProgressPrinter::ProgressPrinter(double duration, bool quiet)
    : duration_(duration), quiet_(quiet), start_(Clock::now()) {}

void ProgressPrinter::operator()(double fraction, const std::string& status) {
  if (quiet_) return;
  const double wall = std::chrono::duration<double>(Clock::now() - start_).count();
  if (wall - last_ < kProgressPeriodSeconds && fraction < 1.0) return;
  last_ = wall;
  const double rtf = wall > 0 ? fraction * duration_ / wall : 0.0;
  const double eta = fraction > 0 ? std::max(0.0, wall * (1.0 - fraction) / fraction) : 0.0;
  std::fprintf(stderr, "[%3.0f%%] t = %.1f / %.1f s, %.0fx real time, ETA %.0f s%s%s\n",
               100 * fraction, fraction * duration_, duration_, rtf, eta,
               status.empty() ? "" : ", ", status.c_str());
}

}  // namespace flagella
