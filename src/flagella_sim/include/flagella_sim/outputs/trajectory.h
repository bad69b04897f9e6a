// Time series of a run (docs/model.md 7.1 quantities per sample) and its steady-window summary.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "flagella_sim/core/types.h"
#include "flagella_sim/core/units.h"

namespace flagella {

struct TrajectorySample {
  double time = 0.0;
  Vec3 head_position = Vec3::Zero();  ///< x_1
  Vec3 head_axis = Vec3::UnitZ();     ///< t^0 (points from the nose toward the tails)
  Eigen::Quaterniond head_orientation =
      Eigen::Quaterniond::Identity();  ///< frame (m1^0, m2^0, t^0)
  double head_angle = 0.0;             ///< theta^0 [rad], cumulative (head spin about t^0)
  double tail_angle = 0.0;             ///< theta^1 [rad], cumulative (shaft/disc/tails spin)
  double omega_h = 0.0;                ///< signed theta_dot^0 [rad/s]
  double omega_t = 0.0;                ///< signed theta_dot^1 [rad/s]
  double omega_T = 0.0;                ///< motor command [rad/s]
  double omega_motor = 0.0;  ///< motor speed applied to the natural twist [rad/s] (= omega_T
                             ///< unless an effect such as dc_motor modifies it)
  Vec3 head_velocity = Vec3::Zero();
  double yaw = 0.0;  ///< azimuth of the forward direction (-t^0) about the world vertical [rad]
  double yaw_rate = 0.0;  ///< its instantaneous rate [rad/s] (docs/model.md 7.1 omega_yr)
  /// Angle between t^0 and the helix's principal axis [rad] (helical robot only, else 0;
  /// docs/model.md 8.4.4).
  double flagellum_tilt = 0.0;
  long newton_iterations = 0;  ///< cumulative since t = 0
  long subdivided_steps = 0;   ///< cumulative count of steps that needed subdivision
  long damped_steps = 0;       ///< cumulative count of (sub)steps solved by the damped retry
  std::vector<Vec3> nodes;     ///< all node positions (only if recorded)
};

/// Steady-state metrics over the last part of a run (docs/model.md 7.1).
struct SummaryMetrics {
  double window_start = 0.0, window_end = 0.0;
  double omega_h = 0.0;  ///< |head spin| [rad/s] from the angle turned in the window
  double omega_t = 0.0;  ///< |tail spin| [rad/s]
  double omega_h_signed = 0.0, omega_t_signed = 0.0;
  double omega_T_mean = 0.0;      ///< mean |motor command| [rad/s]
  double omega_motor_mean = 0.0;  ///< mean |applied motor speed| [rad/s]
  double speed = 0.0;             ///< v: slope of forward displacement along the initial axis [m/s]
  double net_speed = 0.0;         ///< |net displacement| / window length [m/s]
  double path_speed = 0.0;        ///< mean |v_x1| [m/s]
  double yaw_rate = 0.0;       ///< omega_yr: d(psi)/dt of the head axis about the vertical [rad/s]
  double circle_radius = 0.0;  ///< R_yr: least-squares circle of the horizontal x_1 path [m]
  bool circle_valid = false;
  double axis_path_angle = 0.0;  ///< mean angle between head axis and path tangent [rad]
  double efficiency = 0.0;       ///< eta = 3 C_t v / (4 C_r a omega_h) (0 if no head drag)
  bool efficiency_valid = false;
  /// Angle between the head axis of the first and of the last sample (whole run) [rad].
  double heading_change = 0.0;
  /// Largest flagellum tilt in the steady window [rad] (docs/model.md 8.4.4).
  double flagellum_tilt_max = 0.0;
  /// Mean flagellum tilt over the steady window [rad] (docs/model.md 8.4.4): the "tilt" column
  /// of a measured table.
  double flagellum_tilt_mean = 0.0;
  bool buckled = false;        ///< flagellum_tilt_max > SummaryInputs::buckling_tilt
  long newton_iterations = 0;  ///< over the whole run
  long subdivided_steps = 0;   ///< over the whole run
  long damped_steps = 0;       ///< over the whole run
};

struct SummaryInputs {
  Vec3 up = Vec3::UnitZ();  ///< world vertical (the samples' yaw must use the same)
  Vec3 initial_axis = Vec3::UnitZ();
  double steady_fraction = 0.5;
  double C_t = 0.0, C_r = 0.0, head_radius = 0.0;  ///< for eta; C_r = 0 disables it
  double buckling_tilt = units::degToRad(15.0);    ///< threshold of `buckled` [rad]
};

SummaryMetrics summarize(const std::vector<TrajectorySample>& samples, const SummaryInputs& in);

}  // namespace flagella
