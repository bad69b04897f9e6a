// Open-loop planning (docs/model.md 7.3): a prescribed path becomes a switching schedule of the
// single binary input, computed offline from the calibration. Straight lines are periodic
// switching, corners hold one sign for the turn angle (the sides are shortened so that the arc the
// robot sweeps while turning lands it on the next side), arcs use unequal half-periods.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "flagella_control/calibration.h"
#include "flagella_control/path.h"

namespace flagella::control {

struct SwitchInterval {
  double start = 0.0;     ///< [s] from the start of the schedule
  double duration = 0.0;  ///< [s]
  std::int8_t sign = 1;   ///< +1: +omega, -1: -omega
  int element = 0;        ///< path element it serves
};

struct SwitchSchedule {
  std::vector<SwitchInterval> intervals;  ///< contiguous, in time order
  double duration = 0.0;                  ///< end of the last interval [s]
  /// The interval containing time t from the start; nullptr before 0 and from the end on.
  /// O(log n), allocation-free.
  const SwitchInterval* intervalAt(double t) const;
  /// Sign at time t from the start (0 outside the schedule).
  int signAt(double t) const {
    const SwitchInterval* interval = intervalAt(t);
    return interval ? interval->sign : 0;
  }
};

/// Half-period offset epsilon that makes a switching period of length T turn by `turn` [rad]:
/// +omega for T/2 + epsilon, then -omega for T/2 - epsilon (docs/model.md 7.3; the calibrated drift
/// of equal halves is removed as well).
double halfPeriodOffset(const BinaryCalibration& calibration, double turn);

/// Heading at the start of a switching period that makes the net advance go along `direction`.
double periodStartHeading(const BinaryCalibration& calibration, double direction);

/// Displacement of the head centre while one sign is held from heading `heading` until the
/// heading has changed by `turn` (same sign as that sign's yaw rate), in the world frame [m].
Vec2 holdDisplacement(const SignResponse& response, double heading, double turn);

/// Motion over one switching period of the calibration's length T: +omega for `plus_duration`
/// (0..T), then -omega for the rest, begun at `heading`.
struct PeriodMotion {
  Vec2 displacement = Vec2::Zero();  ///< of the head centre, world frame [m]
  double turn = 0.0;                 ///< heading change [rad]
};
/// Integrates the steady constant-sign responses over both parts of the period, then scales and
/// rotates the displacement so that equal halves reproduce the measured advance per period
/// and its angle (what the steady responses miss: the transient after each switch).
PeriodMotion predictPeriod(const BinaryCalibration& calibration, double heading,
                           double plus_duration);

/// Plans `laps` laps (1 for open paths). The path must start at the robot, with the robot's
/// direction of advance along the first element. Throws std::invalid_argument when the path
/// cannot be flown with this calibration (a side too short for the turn before and after it,
/// an arc tighter than periodic switching can steer), naming the element and the limit.
SwitchSchedule planSchedule(const Path& path, const BinaryCalibration& calibration, int laps = 1);

}  // namespace flagella::control
