// The latest camera fix, held until the first IMU sample stamped after it, as every shell of a
// controller core hands it over (the ROS nodes, the LCM shell). A simulator sends a fix and the
// IMU sample of the same instant on two channels, and which one arrives first is up to the
// transport; by the next sample (in lockstep, a whole round trip later) the fix has always
// arrived. So a fix reaches the controller one IMU period after it was taken, whatever the
// transport, and a session gives the same result over ROS and over LCM, every time it runs.
#pragma once

#include <cmath>

#include "flagella_control/controller_core.h"

namespace flagella::control {

class PendingFix {
 public:
  /// Keeps the fix taken at `stamp` [s] when its coordinates are finite (z too only with
  /// `with_height`; without, z is set to 0).
  void offer(double x, double y, double z, double stamp, bool with_height = true) {
    if (!std::isfinite(x) || !std::isfinite(y) || (with_height && !std::isfinite(z))) return;
    position_[0] = x;
    position_[1] = y;
    position_[2] = with_height ? z : 0.0;
    stamp_ = stamp;
    pending_ = true;
  }
  /// Sets in.position_valid: true, with in.position, when a fix taken before in.time is pending
  /// (and then forgets it).
  void deliverBefore(ControllerInputs& in) {
    in.position_valid = pending_ && stamp_ < in.time;
    if (!in.position_valid) return;
    for (int k = 0; k < 3; ++k) in.position[k] = position_[k];
    pending_ = false;
  }

 private:
  double position_[3] = {0.0, 0.0, 0.0};
  double stamp_ = 0.0;
  bool pending_ = false;
};

/// One controller step on `in`, with the pending camera fix if it was taken before the IMU
/// sample; `in` leaves without a position.
inline ControllerOutputs stepWithLatestFix(ControllerCore& controller, ControllerInputs& in,
                                           PendingFix& fix) {
  fix.deliverBefore(in);
  const ControllerOutputs out = controller.step(in);
  in.position_valid = false;
  return out;
}

}  // namespace flagella::control
