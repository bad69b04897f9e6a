// Progress lines of long headless runs on stderr:
//   "[ 42%] t = 84.0 / 200.0 s, 31x real time, ETA 4 s"   (plus an optional status text)
// at most every two seconds of wall time and once at the end.
#pragma once

#include <chrono>
#include <string>

namespace flagella {

class ProgressPrinter {
 public:
  ProgressPrinter(double duration, bool quiet);

  /// `fraction` of the simulated duration done; `status` is appended after a comma.
  void operator()(double fraction, const std::string& status = "");

 private:
  using Clock = std::chrono::steady_clock;
  double duration_;
  bool quiet_;
  Clock::time_point start_;
  double last_ = 0.0;
};

}  // namespace flagella
