// The mass-transformer controller's cycle pitch (SteeringGains::cycle_pitch; docs/model.md 7.4):
// buckle cycles for the whole turn, the slider held off its park estimate through each cycle by
// the offset whose calibrated up-turn brings the cycle's predicted turn to the elevation error,
// and the park estimate learnt from each cycle's measured up-turn.
#include <algorithm>
#include <cmath>

#include "flagella_control/head_attitude.h"
#include "flagella_control/heading.h"
#include "flagella_control/mass_transformer_controller.h"

namespace flagella::control {

namespace {
constexpr int kPhaseSamples = 72;  // phases searched for the best cycle
}  // namespace

double MassTransformerController::cyclePitchCommand(double time) {
  // docs/model.md 7.4: a cycle's phase and the slider's offset held through it chosen together,
  // so that its predicted turn (phase law plus the offset's turn) comes nearest the error.
  const double cruise = calibration_.cruise_omega;
  const double up_error = status_.target_elevation - elevation_;
  const double left_error = status_.azimuth_error * std::cos(elevation_);
  const bool wants_turn = std::hypot(up_error, left_error) > gains_.turn_threshold &&
                          time >= next_cycle_allowed_ && !status_.imu_stale;
  if (!wants_turn) return cruise;
  const double wanted_up = std::clamp(up_error, -gains_.max_cycle_up, gains_.max_cycle_up);
  const double wanted_left = std::clamp(left_error, -gains_.max_cycle_up, gains_.max_cycle_up);
  // The miss of a cycle at phase chi: what it leaves of the wanted turn.
  const auto miss = [&](double chi, double& offset, double& up, double& left) {
    schedule_->turnToward(chi, up, left);
    offset = cycleOffsetFor(wanted_up, up);
    up += schedule_->up_per_slider * offset;
    left += schedule_->left_per_slider * offset;
    return std::hypot(wanted_up - up, wanted_left - left);
  };
  double best = INFINITY, offset = 0.0, up = 0.0, left = 0.0;
  for (int k = 0; k < kPhaseSamples; ++k)
    best = std::min(best, miss(2.0 * M_PI * k / kPhaseSamples, offset, up, left));
  const double now = miss(schedule_->direction(roll_, shaft_), offset, up, left);
  // Start within phase_window of the best phase's miss, and only if the cycle helps.
  const double window = schedule_->deflection * (1.0 - std::cos(gains_.phase_window));
  if (now > best + window || now >= std::hypot(wanted_up, wanted_left)) return cruise;
  status_.in_cycle = true;
  ++status_.cycles;
  cycle_start_ = time;
  cycle_up_ = cycle_pred_up_ = up;
  cycle_pred_left_ = left;
  cycle_before_ = direction_;
  status_.cycle_offset = offset;
  return schedule_->omegaAt(0.0, cruise);
}

double MassTransformerController::cycleOffsetFor(double wanted_up, double phase_up) const {
  return std::clamp((wanted_up - phase_up) / schedule_->up_per_slider, -gains_.max_cycle_offset,
                    gains_.max_cycle_offset);
}

void MassTransformerController::learnPark() {
  // A cycle's measured up-turn less the predicted one is the offset's error: the slider was that
  // much further from park than the estimate said (up_per_slider per metre).
  if (!cycle_to_measure_ || last_time_ < next_cycle_allowed_) return;
  cycle_to_measure_ = false;
  const NormalPlane plane = normalPlane(cycle_before_);
  const double up = (direction_ - cycle_before_).dot(plane.u);
  const double shift =
      std::clamp(-gains_.park_learning * (up - cycle_pred_up_) / schedule_->up_per_slider,
                 -gains_.max_cycle_offset, gains_.max_cycle_offset);
  status_.park_estimate = std::clamp(status_.park_estimate + shift, sliderLow(), sliderHigh());
  ++status_.park_updates;
}

}  // namespace flagella::control
