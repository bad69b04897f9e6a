// The mass-transformer controller's turns in place (SteeringGains::reorient; docs/model.md 7.4):
// the slider's offset pitches the robot the same way whichever way the motor turns, while the
// turn that comes with the pitch changes side with the motor's direction. So the four
// combinations of offset sign and motor direction turn the direction of travel along the four
// diagonals (up-right, up-left, down-left, down-right), and alternating two of them turns it
// along one axis alone while the robot stays nearly in place (forward, then back).
#include <algorithm>
#include <cmath>

#include "flagella_control/mass_transformer_controller.h"

namespace flagella::control {

double MassTransformerController::reorientCommand(double time) {
  const double cruise = calibration_.cruise_omega;
  const double up_error = status_.target_elevation - elevation_;
  const double left_error = status_.azimuth_error * std::cos(elevation_);
  const double size = std::hypot(up_error, left_error);
  if (!status_.reorienting) {
    if (size <= gains_.reorient_enter || time < next_cycle_allowed_ || status_.imu_stale)
      return cruise;
    status_.reorienting = true;
    reorient_until_ = time;
  }
  // While turning, the estimator follows the lightly filtered head axis and learns no crab (as
  // during a turn at elevation).
  holdoff_until_ = std::max(holdoff_until_, time + gains_.reorient_dwell);
  // Ended as soon as the error is within reorient_exit (it sweeps through it mid-dwell).
  if (size <= gains_.reorient_exit) {
    status_.reorienting = false;
    status_.cycle_offset = 0.0;
    next_cycle_allowed_ = time + gains_.settle_time;
    return cruise;
  }
  if (time >= reorient_until_) {
    // The diagonal nearest the error; a small component alternates its sign, so that the
    // combinations' pitch (or turn) cancels while the other component is taken.
    const double balance = gains_.reorient_balance * size;
    reorient_up_ = std::abs(up_error) > balance ? std::copysign(1.0, up_error) : -reorient_up_;
    reorient_left_ =
        std::abs(left_error) > balance ? std::copysign(1.0, left_error) : -reorient_left_;
    // Forward, an offset pitching up turns right (reorient_up_turns_right); reversed, left.
    const double right_when_up = gains_.reorient_up_turns_right ? 1.0 : -1.0;
    reorient_motor_ = reorient_up_ * reorient_left_ * right_when_up < 0.0 ? 1.0 : -1.0;
    const double share =
        std::clamp(size / gains_.reorient_full_error, gains_.reorient_min_share, 1.0);
    status_.cycle_offset = reorient_up_ * std::copysign(share * gains_.reorient_offset,
                                                        calibration_.pitch_rate_per_slider);
    reorient_until_ = time + gains_.reorient_dwell;
    ++status_.reorient_dwells;
  }
  return reorient_motor_ * gains_.reorient_omega;
}

}  // namespace flagella::control
