// A hand-made constant-sign response for tests: yaw rate and body-frame velocity, with the
// derived fields (speed, circle radius, axis-path angle) consistent with steady circling.
#pragma once

#include <cmath>

#include "flagella_control/calibration.h"

namespace flagella::control::testing {

inline SignResponse signResponse(double yaw_rate, double v_along, double v_left) {
  SignResponse r;
  r.yaw_rate = yaw_rate;
  r.body_velocity[0] = v_along;
  r.body_velocity[1] = v_left;
  r.speed = std::hypot(v_along, v_left);
  r.circle_radius = r.speed / std::abs(yaw_rate);
  r.axis_path_angle = std::atan2(v_left, v_along);
  return r;
}

}  // namespace flagella::control::testing
