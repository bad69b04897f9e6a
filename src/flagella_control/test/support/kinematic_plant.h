// The kinematic test plant of the path-following controllers: a hand-made calibration, a plant
// that moves exactly with its steady sign responses (yaw rates optionally scaled: a model error),
// closed-loop runs with IMU and camera inputs (noise, dropouts), and start-frame test paths.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "flagella_control/path_controllers.h"
#include "flagella_sim/core/units.h"
#include "sign_response.h"

namespace flagella::control::testing {

namespace fc = flagella::control;
namespace units = flagella::units;
using fc::Path;
using fc::Vec2;

constexpr double kRate = 100.0;   // controller [Hz]
constexpr int kCameraEvery = 50;  // camera at 2 Hz

// ---- calibration ------------------------------------------------------------------------------

/// The calibration flagella_calibrate would measure on the plant (below) with its yaw rates and
/// sideways velocities `lateral_scale` times these hand-made round numbers (omega 4.5 rad/s,
/// T = 10 s, yaw rates -/+0.03 rad/s, body velocities {-1, +3} and {-1, -3} mm/s): the advance
/// per period and its angle integrated finely over one period (at scale 1: 9.99 mm at
/// 0.075 rad; the heading swings 0.15 rad and back within a period).
inline fc::BinaryCalibration plantCalibration(double lateral_scale) {
  fc::BinaryCalibration c;
  c.omega = 4.5;
  c.switch_period = 10.0;
  // The interface robot's chirality (config/calibration): +omega turns clockwise and slides
  // to the right of the direction of advance, which is opposite to the head axis.
  c.plus = fc::testing::signResponse(-0.03 * lateral_scale, -1e-3, +3e-3 * lateral_scale);
  c.minus = fc::testing::signResponse(+0.03 * lateral_scale, -1e-3, -3e-3 * lateral_scale);
  Vec2 p = Vec2::Zero();
  double h = 0.0;
  const double dt = 1e-4;
  for (const fc::SignResponse* r : {&c.plus, &c.minus}) {
    const Vec2 v(r->body_velocity[0], r->body_velocity[1]);
    for (int i = 0; i < 50000; ++i) {  // midpoint rule, T/2 = 5 s
      p += Eigen::Rotation2Dd(h + 0.5 * dt * r->yaw_rate) * v * dt;
      h += r->yaw_rate * dt;
    }
  }
  c.advance_per_period = p.norm();
  c.advance_angle = std::atan2(p.y(), p.x());
  c.heading_drift_per_period = 0.0;
  c.source = "hand-made (test)";
  return c;
}

/// The nominal hand-made calibration (plantCalibration at scale 1).
inline fc::BinaryCalibration nominalCalibration() { return plantCalibration(1.0); }

// ---- the plant ----------------------------------------------------------------------------------

struct Plant {
  fc::SignResponse plus, minus;
  Vec2 p = Vec2::Zero();
  double h = 0.0;  ///< heading, unwrapped

  /// Yaw rates scaled per sign; `sideways_scale` scales the sideways body velocities too (with
  /// the yaw rates: an error in the lateral force, as C_yr makes).
  Plant(const fc::BinaryCalibration& c, double plus_scale = 1.0, double minus_scale = 1.0,
        double sideways_scale = 1.0)
      : plus(c.plus), minus(c.minus) {
    plus.yaw_rate *= plus_scale;
    minus.yaw_rate *= minus_scale;
    plus.body_velocity[1] *= sideways_scale;
    minus.body_velocity[1] *= sideways_scale;
  }
  void step(int sign, double dt) {
    if (sign == 0) return;
    const fc::SignResponse& r = sign > 0 ? plus : minus;
    p += Eigen::Rotation2Dd(h) * Vec2(r.body_velocity[0], r.body_velocity[1]) * dt;
    h += r.yaw_rate * dt;
  }
  /// Head axis (body z) horizontal at azimuth h: q = Rz(h) Ry(+90 deg).
  Eigen::Quaterniond orientation() const {
    return Eigen::AngleAxisd(h, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  }
};

// ---- closed-loop runs -------------------------------------------------------------------------

struct Scenario {
  double plus_scale = 1.0, minus_scale = 1.0;  ///< plant yaw rates / nominal
  double sideways_scale = 1.0;                 ///< plant sideways velocities / nominal
  double camera_noise = 0.0;                   ///< [m], Gaussian per axis
  unsigned seed = 1;
  Vec2 start = Vec2(0.1, -0.2);
  double start_heading = 0.4;
  double imu_off_from = -1.0, imu_off_to = -1.0;  ///< IMU invalid in [from, to)
  double camera_off_from = -1.0, camera_off_to = -1.0;
  double imu_on_at = 0.0;      ///< no IMU sample before this time
  double t_max = 4000.0;       ///< [s]
  double after_finish = 50.0;  ///< keep stepping this long after Finished [s]
};

struct Result {
  bool finished = false;
  double finish_time = NAN;
  double max_ct = 0.0, rms_ct = 0.0;  ///< true cross-track error while running [m]
  long samples = 0;
  bool motor_zero_after_finish = true, stayed_finished = true;
  bool saw_imu_stale = false, saw_fix_stale = false;
  std::string imu_stale_message, fix_stale_message;
  bool fault = false;
  double fault_time = NAN;
  bool motor_zero_in_fault = true;
  std::vector<int> signs;  ///< applied sign per step
  std::vector<fc::ControllerMode> modes;
  std::vector<double> heading_error;  ///< status().heading_error per step
  std::vector<double> progress;       ///< status().progress per step
  std::vector<double> true_ct;        ///< true distance to the path per step (0 unless running)
  Vec2 end = Vec2::Zero();
  double end_heading = 0.0;
};

inline Result run(fc::PathControllerBase& ctrl, const fc::BinaryCalibration& nominal,
                  const Scenario& sc) {
  Plant plant(nominal, sc.plus_scale, sc.minus_scale, sc.sideways_scale);
  plant.p = sc.start;
  plant.h = sc.start_heading;
  std::mt19937 rng(sc.seed);
  std::normal_distribution<double> noise(0.0, sc.camera_noise > 0 ? sc.camera_noise : 1.0);
  Result res;
  double sum_sq = 0.0;
  const long n_max = static_cast<long>(sc.t_max * kRate);
  long finish_step = -1;
  for (long i = 0; i < n_max; ++i) {
    const double t = i / kRate;
    fc::ControllerInputs in;
    in.time = t;
    in.imu_valid = t >= sc.imu_on_at && !(t >= sc.imu_off_from && t < sc.imu_off_to);
    const Eigen::Quaterniond q = plant.orientation();
    in.orientation[0] = q.x();
    in.orientation[1] = q.y();
    in.orientation[2] = q.z();
    in.orientation[3] = q.w();
    in.position_valid = i % kCameraEvery == 0 && !(t >= sc.camera_off_from && t < sc.camera_off_to);
    if (in.position_valid) {
      const bool noisy = sc.camera_noise > 0;
      in.position[0] = plant.p.x() + (noisy ? noise(rng) : 0.0);
      in.position[1] = plant.p.y() + (noisy ? noise(rng) : 0.0);
    }
    const fc::ControllerOutputs out = ctrl.step(in);
    const int sign = (out.motor_command > 0) - (out.motor_command < 0);
    res.signs.push_back(sign);
    res.modes.push_back(out.mode);
    res.heading_error.push_back(ctrl.status().heading_error);
    res.progress.push_back(ctrl.status().progress);
    const fc::PathStatus& st = ctrl.status();
    if (st.imu_stale && !res.saw_imu_stale) {
      res.saw_imu_stale = true;
      res.imu_stale_message = st.message;
    }
    if (st.fix_stale && !res.saw_fix_stale && out.mode == fc::ControllerMode::Running) {
      res.saw_fix_stale = true;
      res.fix_stale_message = st.message;
    }
    if (out.mode == fc::ControllerMode::Running) {
      const double ct = ctrl.worldPath().project(plant.p).distance;
      res.true_ct.push_back(ct);
      res.max_ct = std::max(res.max_ct, ct);
      sum_sq += ct * ct;
      ++res.samples;
    } else {
      res.true_ct.push_back(0.0);
    }
    if (out.mode == fc::ControllerMode::Fault) {
      if (!res.fault) res.fault_time = t;
      res.fault = true;
      if (out.motor_command != 0.0) res.motor_zero_in_fault = false;
    }
    if (finish_step >= 0) {
      if (out.motor_command != 0.0) res.motor_zero_after_finish = false;
      if (out.mode != fc::ControllerMode::Finished) res.stayed_finished = false;
      if (i - finish_step >= static_cast<long>(sc.after_finish * kRate)) break;
    } else if (out.mode == fc::ControllerMode::Finished) {
      res.finished = true;
      res.finish_time = t;
      finish_step = i;
      if (out.motor_command != 0.0) res.motor_zero_after_finish = false;
    }
    plant.step(sign, 1.0 / kRate);
  }
  res.rms_ct = res.samples ? std::sqrt(sum_sq / res.samples) : 0.0;
  res.end = plant.p;
  res.end_heading = plant.h;
  return res;
}

inline fc::PathSpec startFrameRectangle(double w = 0.3, double h = 0.3) {
  fc::PathSpec s;
  s.path = Path::polyline({{0, 0}, {w, 0}, {w, h}, {0, h}}, true);
  s.frame = fc::PathFrame::Start;
  s.description = "rectangle (test)";
  return s;
}

inline fc::PathSpec startFrameCircle(double r = 0.2) {
  fc::PathSpec s;
  s.path = Path::circle({0, 0}, 0.0, r, true);
  s.frame = fc::PathFrame::Start;
  s.description = "circle (test)";
  return s;
}

inline fc::PathSpec startFramePolyline() {
  fc::PathSpec s;
  s.path = Path::polyline({{0, 0}, {0.2, 0}, {0.35, 0.15}, {0.5, 0}}, false);
  s.frame = fc::PathFrame::Start;
  s.description = "open zigzag (test)";
  return s;
}

inline void print(const char* label, const Result& r) {
  std::printf(
      "[ control  ] %-52s finished %-3s at %7.1f s  cross-track max %6.1f mm  RMS %6.1f mm\n",
      label, r.finished ? "yes" : "NO", r.finish_time, units::metresToMm(r.max_ct),
      units::metresToMm(r.rms_ct));
}

}  // namespace flagella::control::testing
