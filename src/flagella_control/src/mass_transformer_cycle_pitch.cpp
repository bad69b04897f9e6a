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
// Turn learning: a turn smaller than this share of the calibrated size gives no direction; one
// within these of the prediction (direction, size ratio) lets the park estimate learn.
constexpr double kDirectionShare = 0.3;
constexpr double kAgreedDirection = 0.35;  // [rad]
constexpr double kAgreedSizeRatio = 1.5;
constexpr double kLargestSizeRatio = 16.0;  // a size error counts at most ln of this
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
  const double wanted = std::hypot(wanted_up, wanted_left);
  if (gains_.turn_learning > 0.0) {
    sizeCycle(wanted, size_log_, schedule_);
    if (gains_.mixed_schedules) sizeCycle(wanted, other_size_log_, other_schedule_);
  }
  double best = bestMiss(schedule_, wanted_up, wanted_left);
  if (gains_.mixed_schedules) {  // the schedule whose best phase comes nearer
    const double other = bestMiss(other_schedule_, wanted_up, wanted_left);
    if (other < best) {
      std::swap(schedule_, other_schedule_);
      std::swap(size_log_, other_size_log_);
      best = other;
    }
  }
  const double chi = schedule_.direction(roll_, shaft_);
  double offset = 0.0, up = 0.0, left = 0.0;
  const double now = cycleMiss(schedule_, chi, wanted_up, wanted_left, offset, up, left);
  // Start within phase_window of the best phase's miss, and only if the cycle helps.
  const double window = schedule_.deflection * (1.0 - std::cos(gains_.phase_window));
  if (now > best + window || now >= wanted) return cruise;
  status_.in_cycle = true;
  ++status_.cycles;
  cycle_start_ = time;
  cycle_up_ = cycle_pred_up_ = up;
  cycle_before_ = direction_stage_;  // the first stage: less lag for the measurement
  status_.cycle_offset = cycle_offset_ = offset;
  cycle_chi_ = chi;
  cycle_size_ = schedule_.deflection;
  status_.pulse_omega = schedule_.pulse_omega;
  return schedule_.omegaAt(0.0, cruise);
}

double MassTransformerController::cycleMiss(const BuckleSchedule& schedule, double chi,
                                            double wanted_up, double wanted_left, double& offset,
                                            double& up, double& left) const {
  // What a cycle of this schedule at phase chi, with its offset, leaves of the wanted turn.
  schedule.turnToward(chi, up, left);
  offset = std::clamp((wanted_up - up) / schedule.up_per_slider, -gains_.max_cycle_offset,
                      gains_.max_cycle_offset);
  up += schedule.up_per_slider * offset;
  left += schedule.left_per_slider * offset;
  return std::hypot(wanted_up - up, wanted_left - left);
}

double MassTransformerController::bestMiss(const BuckleSchedule& schedule, double wanted_up,
                                           double wanted_left) const {
  double best = INFINITY, offset = 0.0, up = 0.0, left = 0.0;
  for (int k = 0; k < kPhaseSamples; ++k)
    best = std::min(best, cycleMiss(schedule, 2.0 * M_PI * k / kPhaseSamples, wanted_up,
                                    wanted_left, offset, up, left));
  return best;
}

void MassTransformerController::learnPark() {
  // A cycle's measured up-turn less the predicted one is the offset's error: the slider was that
  // much further from park than the estimate said (up_per_slider per metre).
  if (!cycle_to_measure_ || last_time_ < next_cycle_allowed_) return;
  cycle_to_measure_ = false;
  const NormalPlane plane = normalPlane(cycle_before_);
  const double up = (direction_stage_ - cycle_before_).dot(plane.u);
  const double left = (direction_stage_ - cycle_before_).dot(plane.w);
  if (gains_.turn_learning > 0.0 && !learnTurn(up, left)) return;
  const double shift =
      std::clamp(-gains_.park_learning * (up - cycle_pred_up_) / schedule_.up_per_slider,
                 -gains_.max_cycle_offset, gains_.max_cycle_offset);
  status_.park_estimate = std::clamp(status_.park_estimate + shift, sliderLow(), sliderHigh());
  ++status_.park_updates;
}

void MassTransformerController::sizeCycle(double wanted, double size_log,
                                          BuckleSchedule& schedule) const {
  // docs/model.md 7.4: the pulse rate whose predicted turn by phase has the wanted size; the
  // turn grows as exp(pulse_growth x pulse factor) from the calibrated pulse's, times the
  // learnt turn_gain.
  const BuckleSchedule& calibrated = calibration_.schedule(schedule.kind);
  const double threshold = calibration_.buckling_threshold;
  const double calibrated_factor = calibrated.pulse_omega / threshold;
  const double size = std::clamp(wanted, std::min(gains_.turn_threshold, gains_.max_cycle_turn),
                                 gains_.max_cycle_turn);
  // pulse_growth 0: the calibrated pulse, its turn as learnt.
  const double factor =
      gains_.pulse_growth == 0.0
          ? calibrated_factor
          : std::clamp(calibrated_factor + (std::log(size / calibrated.deflection) - size_log) /
                                               gains_.pulse_growth,
                       gains_.min_pulse_factor, gains_.max_pulse_factor);
  const double ratio = std::exp(size_log + gains_.pulse_growth * (factor - calibrated_factor));
  schedule.pulse_omega = factor * threshold;
  schedule.deflection = calibrated.deflection * ratio;
  // The offset's couple pitches the robot at the cruising rate through the cycle whatever the
  // buckle; the rest of its up-turn, and its left-turn, are amplified.
  const double pitching = calibration_.pitch_rate_per_slider * calibrated.cycleDuration();
  schedule.up_per_slider = pitching + (calibrated.up_per_slider - pitching) * ratio;
  schedule.left_per_slider = calibrated.left_per_slider * ratio;
}

bool MassTransformerController::learnTurn(double up, double left) {
  // docs/model.md 7.4: the phase-dependent part of the measured turn (less the constant part
  // and the offset's turn) against the predicted size and direction chi.
  const double phase_up = up - schedule_.bias_up - schedule_.up_per_slider * cycle_offset_;
  const double phase_left = left - schedule_.bias_left - schedule_.left_per_slider * cycle_offset_;
  const double size = std::hypot(phase_up, phase_left);
  const double size_error =
      std::log(std::clamp(size, cycle_size_ / kLargestSizeRatio, cycle_size_ * kLargestSizeRatio) /
               cycle_size_);
  size_log_ += gains_.turn_learning * size_error;
  status_.turn_gain = std::exp(size_log_);
  const double direction_error = wrapAngle(std::atan2(phase_left, phase_up) - cycle_chi_);
  const bool has_direction = size > kDirectionShare * cycle_size_;
  if (has_direction) {
    schedule_.phase_offset =
        wrapAngle(schedule_.phase_offset + gains_.turn_learning * direction_error);
    status_.phase_shift =
        wrapAngle(schedule_.phase_offset - calibration_.schedule(schedule_.kind).phase_offset);
  }
  ++status_.turn_updates;
  return has_direction && std::abs(direction_error) < kAgreedDirection &&
         std::abs(size_error) < std::log(kAgreedSizeRatio);
}

}  // namespace flagella::control
