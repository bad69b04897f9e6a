// Design 1 granular robot of docs/model.md 8.1 at omega_T = 100 rpm with the shipped config: the
// robot swims head first, the head takes most of the motor's rotation, and two tails swim faster
// than three ([CORR-16]: v decreases as n increases), with the tails of the 3-tail robot turning
// slower. Metrics are recomputed here from the sampled trajectory (docs/model.md 7.1) and compared
// with summary().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace {

constexpr double kMotorRpm = 100.0;
// 40 s: on 120 s runs the head spin and the speed are constant to 5-6 digits from ~20 s on, for
// n = 2 and n = 3, so the steady window is the last half (20 s .. 40 s).
constexpr double kRunDuration = 40.0;
constexpr double kSteadyFraction = 0.5;
// The two halves of the steady window must agree on speed and spins: a transient still decaying
// (tail relaxation time eta_p L^4/(12.4 EI) ~ 2 s) would show up here. Measured < 1e-5.
constexpr double kSteadinessTolerance = 0.01;
// Recomputed metrics vs summary(): same samples, same definitions; only rounding differs.
constexpr double kMetricAgreement = 1e-6;
// Straight swimming: sideways drift of x_1 relative to the forward displacement. The robot is
// symmetric about its axis, so any drift is round-off; 1 % still catches a yawing robot.
constexpr double kLateralDriftFraction = 0.01;
// Head spin as a share of omega_T: the fitted head torque prefactor C_r is small, so the head
// turns much more easily than the tails (docs/model.md 8.1); at least half is the required
// property.
constexpr double kHeadSpinShare = 0.5;

double motorOmega() { return units::rpmToRadPerSec(kMotorRpm); }

std::unique_ptr<Simulation> runDesign1(int n_tails) {
  const std::vector<std::string> overrides = {
      "robot.n_tails=" + std::to_string(n_tails), "motor.omega_rpm=" + std::to_string(kMotorRpm),
      "simulation.duration=" + std::to_string(kRunDuration),
      "simulation.steady_fraction=" + std::to_string(kSteadyFraction)};
  const SimulationConfig config =
      loadSimulationConfig(std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml", overrides);
  auto sim = std::make_unique<Simulation>(config);
  sim->run(kRunDuration);
  return sim;
}

// Spec 7.1 quantities over [t0, t1] from the samples: v = least-squares slope of the forward
// displacement -(x_1 - x_1(0)).ahat_0 (head first = positive), spins = angle turned / time.
struct WindowMetrics {
  double speed = 0.0;
  double omega_h = 0.0;  // signed theta_dot^0
  double omega_t = 0.0;  // signed theta_dot^1
  double forward = 0.0;  // forward displacement over the window [m]
  double lateral = 0.0;  // largest sideways excursion of x_1 from the axis line [m]
};

WindowMetrics windowMetrics(const std::vector<TrajectorySample>& samples, double t0, double t1) {
  const Vec3 axis = samples.front().head_axis.normalized();
  const Vec3 origin = samples.front().head_position;
  double n = 0, st = 0, ss = 0, stt = 0, sts = 0;
  const TrajectorySample* first = nullptr;
  const TrajectorySample* last = nullptr;
  WindowMetrics m;
  for (const TrajectorySample& s : samples) {
    if (s.time < t0 - 1e-9 || s.time > t1 + 1e-9) continue;
    if (!first) first = &s;
    last = &s;
    const Vec3 d = s.head_position - origin;
    const double forward = -d.dot(axis);
    n += 1;
    st += s.time;
    ss += forward;
    stt += s.time * s.time;
    sts += s.time * forward;
    m.lateral = std::max(m.lateral, (d - d.dot(axis) * axis).norm());
  }
  if (!first || first == last) return m;
  m.speed = (n * sts - st * ss) / (n * stt - st * st);
  const double span = last->time - first->time;
  m.omega_h = (last->head_angle - first->head_angle) / span;
  m.omega_t = (last->tail_angle - first->tail_angle) / span;
  m.forward = -(last->head_position - first->head_position).dot(axis);
  return m;
}

struct Design1Result {
  WindowMetrics window;
  SummaryMetrics summary;
};

Design1Result runAndCheck(int n_tails) {
  const auto sim = runDesign1(n_tails);
  const std::vector<TrajectorySample>& traj = sim->trajectory();
  const double t_end = traj.back().time;
  const double t_start = t_end - kSteadyFraction * (t_end - traj.front().time);
  const double t_mid = 0.5 * (t_start + t_end);
  Design1Result r;
  r.summary = sim->summary();
  r.window = windowMetrics(traj, r.summary.window_start, r.summary.window_end);
  const WindowMetrics early = windowMetrics(traj, t_start, t_mid);
  const WindowMetrics late = windowMetrics(traj, t_mid, t_end);
  const double omega_T = motorOmega();
  std::printf(
      "[design 1, n=%d] v %.6e m/s (halves %.6e / %.6e), omega_h %.5f, omega_t %.5f rad/s "
      "(omega_T %.5f), lateral %.2e m over forward %.2e m\n",
      n_tails, r.window.speed, early.speed, late.speed, std::abs(r.window.omega_h),
      std::abs(r.window.omega_t), omega_T, r.window.lateral, r.window.forward);

  // Steady state reached: both halves of the window agree.
  EXPECT_NEAR(early.speed, late.speed, kSteadinessTolerance * std::abs(late.speed));
  EXPECT_NEAR(early.omega_h, late.omega_h, kSteadinessTolerance * std::abs(late.omega_h));
  EXPECT_NEAR(early.omega_t, late.omega_t, kSteadinessTolerance * std::abs(late.omega_t));
  // summary() reports the same docs/model.md 7.1 quantities.
  EXPECT_NEAR(r.summary.speed, r.window.speed, kMetricAgreement * std::abs(r.window.speed));
  EXPECT_NEAR(r.summary.omega_h_signed, r.window.omega_h, kMetricAgreement * omega_T);
  EXPECT_NEAR(r.summary.omega_t_signed, r.window.omega_t, kMetricAgreement * omega_T);

  // Head first (toward -z), along a straight line.
  EXPECT_GT(r.window.speed, 0.0);
  EXPECT_LT(r.window.lateral, kLateralDriftFraction * std::abs(r.window.forward));
  // The head takes most of the rotation.
  EXPECT_GT(std::abs(r.window.omega_h), std::abs(r.window.omega_t));
  EXPECT_GT(std::abs(r.window.omega_h), kHeadSpinShare * omega_T);
  return r;
}

TEST(Design1Robot, TwoTailsSwimFasterThanThreeAndHeadTakesMostRotation) {
  const Design1Result two = runAndCheck(2);
  const Design1Result three = runAndCheck(3);
  std::printf("[design 1] v(n=2) / v(n=3) = %.4f\n", two.window.speed / three.window.speed);
  // [CORR-16]: v decreases as n increases. The margin exceeds the steadiness tolerance so that a
  // not-yet-steady pair cannot pass by accident.
  EXPECT_GT(two.window.speed, (1.0 + 2.0 * kSteadinessTolerance) * three.window.speed);
  // More tails resist the tails' rotation more, so the 3-tail robot's tails turn slower and its
  // head faster (omega_h + omega_t = omega_T).
  EXPECT_GT(std::abs(two.window.omega_t), std::abs(three.window.omega_t));
  EXPECT_LT(std::abs(two.window.omega_h), std::abs(three.window.omega_h));
}

}  // namespace
}  // namespace flagella
