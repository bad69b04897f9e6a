#include "flagella_sim/outputs/trajectory.h"

#include <algorithm>
#include <cmath>

#include "flagella_sim/core/geometry.h"
#include "flagella_sim/outputs/fits.h"

namespace flagella {

namespace {
// Below this horizontal projection length the head axis is treated as vertical (no yaw).
constexpr double kMinHorizontalAxis = 1e-6;
// Speeds below this do not define a path tangent.
constexpr double kMinPathSpeed = 1e-12;

// docs/model.md 8.4.4: heading change over the whole run, flagellum tilt over the steady window
// (samples from `first` on).
void addTurnAndBucklingMetrics(const std::vector<TrajectorySample>& samples, size_t first,
                               const SummaryInputs& in, SummaryMetrics& m) {
  m.heading_change = angleBetween(samples.front().head_axis, samples.back().head_axis);
  double tilt_sum = 0.0;
  for (size_t i = first; i < samples.size(); ++i) {
    m.flagellum_tilt_max = std::max(m.flagellum_tilt_max, samples[i].flagellum_tilt);
    tilt_sum += samples[i].flagellum_tilt;
  }
  m.flagellum_tilt_mean = tilt_sum / static_cast<double>(samples.size() - first);
  m.buckled = m.flagellum_tilt_max > in.buckling_tilt;
}

}  // namespace

SummaryMetrics summarize(const std::vector<TrajectorySample>& samples, const SummaryInputs& in) {
  SummaryMetrics m;
  if (samples.size() < 2) return m;
  const double t_end = samples.back().time;
  const double t_begin = t_end - in.steady_fraction * (t_end - samples.front().time);
  size_t first = 0;
  while (first + 2 < samples.size() && samples[first].time < t_begin) ++first;
  const TrajectorySample& a = samples[first];
  const TrajectorySample& b = samples.back();
  m.window_start = a.time;
  m.window_end = b.time;
  const double span = b.time - a.time;
  if (span <= 0.0) return m;

  // docs/model.md 7.1: omega = turns / time (angle turned in the window)
  m.omega_h_signed = (b.head_angle - a.head_angle) / span;
  m.omega_t_signed = (b.tail_angle - a.tail_angle) / span;
  m.omega_h = std::abs(m.omega_h_signed);
  m.omega_t = std::abs(m.omega_t_signed);

  const Vec3 up = in.up.normalized();
  const Vec3 e1 = anyPerpendicular(up);
  const Vec3 e2 = up.cross(e1);
  std::vector<double> t, forward, yaw;
  std::vector<Eigen::Vector2d> horizontal;
  double angle_sum = 0.0, speed_sum = 0.0, omega_T_sum = 0.0, omega_motor_sum = 0.0;
  int angle_count = 0;
  for (size_t i = first; i < samples.size(); ++i) {
    const TrajectorySample& s = samples[i];
    t.push_back(s.time);
    // docs/model.md 7.1: v = slope of the displacement along the initial axis (forward = head
    // first)
    forward.push_back(-(s.head_position - samples.front().head_position).dot(in.initial_axis));
    horizontal.emplace_back(s.head_position.dot(e1), s.head_position.dot(e2));
    const Vec3 axis_h = s.head_axis - s.head_axis.dot(up) * up;
    yaw.push_back(s.yaw);  // psi: azimuth of the forward direction about the vertical
    const Vec3 v_h = s.head_velocity - s.head_velocity.dot(up) * up;
    speed_sum += s.head_velocity.norm();
    omega_T_sum += std::abs(s.omega_T);
    omega_motor_sum += std::abs(s.omega_motor);
    if (v_h.norm() > kMinPathSpeed && axis_h.norm() > kMinHorizontalAxis) {
      angle_sum += std::acos(std::clamp((-axis_h.normalized()).dot(v_h.normalized()), -1.0, 1.0));
      ++angle_count;
    }
  }
  const double count = static_cast<double>(t.size());
  m.path_speed = speed_sum / count;
  m.omega_T_mean = omega_T_sum / count;
  m.omega_motor_mean = omega_motor_sum / count;
  m.axis_path_angle = angle_count > 0 ? angle_sum / angle_count : 0.0;
  m.net_speed = (b.head_position - a.head_position).norm() / span;
  m.speed = fitLine(t, forward).slope;
  m.yaw_rate = fitLine(t, unwrapAngles(yaw)).slope;  // docs/model.md 7.1: omega_yr = d psi/dt
  const CircleFit circle = fitCircle(horizontal);    // docs/model.md 7.1: R_yr
  m.circle_valid = circle.valid;
  m.circle_radius = circle.valid ? circle.radius : 0.0;
  if (in.C_r > 0.0 && in.head_radius > 0.0 && m.omega_h > 0.0) {
    m.efficiency = 3.0 * in.C_t * m.speed /
                   (4.0 * in.C_r * in.head_radius * m.omega_h);  // docs/model.md 7.1 (Eq. 2.18)
    m.efficiency_valid = true;
  }
  addTurnAndBucklingMetrics(samples, first, in, m);
  m.newton_iterations = samples.back().newton_iterations;
  m.subdivided_steps = samples.back().subdivided_steps;
  m.damped_steps = samples.back().damped_steps;
  return m;
}

}  // namespace flagella
