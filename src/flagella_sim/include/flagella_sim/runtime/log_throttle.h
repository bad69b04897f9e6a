// One log line per period of wall time for a message that can repeat at the step rate (a flood
// of rejected commands), with a count of the lines it held back. ROS-free: the node passes the
// wall clock.
#pragma once

namespace flagella {

class LogThrottle {
 public:
  /// `period` [s]: at most one line per period after the first.
  explicit LogThrottle(double period) : period_(period) {}
  /// True when a line may be written at `now` [s]; `held_back` is then the number of lines
  /// refused since the last one written (0 otherwise).
  bool allow(double now, long& held_back) {
    held_back = 0;
    if (written_ && now - last_ < period_) {
      ++held_;
      return false;
    }
    held_back = held_;
    held_ = 0;
    last_ = now;
    written_ = true;
    return true;
  }

 private:
  double period_;
  double last_ = 0.0;
  bool written_ = false;
  long held_ = 0;
};

}  // namespace flagella
