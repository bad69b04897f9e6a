// Decides when a periodic output is due in simulated time (publishers of the node and of the
// LCM harness use one each).
#pragma once

#include <cmath>

namespace flagella {

class RateSchedule {
 public:
  /// rate in Hz of simulated time; rate <= 0 means "every time it is asked".
  explicit RateSchedule(double rate) : period_(rate > 0.0 ? 1.0 / rate : 0.0) {}
  /// True once per period; the schedule is anchored at the first call, so drift does not build up.
  bool due(double time) {
    if (period_ == 0.0) return true;
    if (!started_ || time + kSlack * period_ >= next_) {
      next_ = started_ ? next_ + period_ * std::floor((time - next_) / period_ + 1.0 + kSlack)
                       : time + period_;
      started_ = true;
      return true;
    }
    return false;
  }
  void restart() { started_ = false; }
  double period() const { return period_; }

 private:
  static constexpr double kSlack = 1e-6;  // fraction of a period: float round-off in time sums
  double period_;
  double next_ = 0.0;
  bool started_ = false;
};

}  // namespace flagella
