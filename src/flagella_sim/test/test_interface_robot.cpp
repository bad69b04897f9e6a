// Physics tests of the interface robot (docs/model.md 3.3, 7.1, 7.3, 8.3): near the air-glycerin
// boundary the rotation-induced lateral head force makes the robot circle about the world vertical
// at constant motor speed; reversing the motor mirrors the circle; periodic sign switching (binary
// control) gives a straight net path; and without the lateral force (C_yr = 0) there is no
// circling.
//
// Every expectation comes from symmetry, kinematics or the spec, never from recorded outputs.
// Yaw angles and circle fits are recomputed here from the raw trajectory, independently of the
// summary code, and compared with it.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace {

// ---- run lengths ----------------------------------------------------------------------------
// The spin rates settle within ~2 s of the 0.5 s ramp (first-mode tail relaxation time
// eta_p l^4 / (1.875^4 EI) = 6.9 s / 12.4 = 0.55 s), so 6 s of transient is discarded.
constexpr double kConstantDuration = 30.0;       // [s] constant-omega runs
constexpr double kConstantSteadyFraction = 0.8;  // window 6..30 s
constexpr int kBinaryPeriods = 10;               // whole +/- periods simulated
constexpr double kMotorRpm = 43.27;              // omegabar = 10 (docs/model.md 7.3, 8.3)

// ---- tolerances -----------------------------------------------------------------------------
// (a) The window must turn the heading by at least this much for "clearly circling" [rad]
//     (the fitted set turns it by ~2.7 rad in 24 s).
constexpr double kMinHeadingTurn = 1.0;
// (a) Steady yaw rate: first vs second half of the window. Measured difference ~1e-6 relative;
//     1 % leaves room for the slow pitch drift (see below) while still catching a non-steady turn.
constexpr double kSteadyYawTolerance = 0.01;
// (a) rms distance of the head path from the fitted circle, relative to the radius. The path is a
//     circle up to a small wobble at the tail-passing frequency (measured ~1e-6).
constexpr double kCircleRmsTolerance = 0.01;
// (a) This file's circle fit and yaw rate vs the summary's (same data, different code): 1e-3.
constexpr double kSummaryAgreement = 1e-3;
// (a) Kinematics of uniform circular motion: R = |v_horizontal| / |omega_yr|. Holds to the
//     wobble of the head path; 2 %.
constexpr double kKinematicTolerance = 0.02;
// (a) The model has no buoyancy or vertical restoring force (docs/model.md 3.3), so the head axis
// pitch
//     drifts slowly; yaw about the vertical is only meaningful while it stays near horizontal.
constexpr double kMaxPitch = units::degToRad(3.0);  // [rad]
// (b) Mirror symmetry makes |yaw rate| and the radius exactly equal for +/-omega up to solver
//     tolerances (measured ~1e-14); 2 % as in docs/model.md's "equal radii".
constexpr double kMirrorTolerance = 0.02;
// (b) Pointwise: the -omega head path is the mirror image of the +omega path. The symmetry is
//     exact, so only Newton-tolerance-level differences are allowed: 1e-4 of R (measured 1e-12).
constexpr double kMirrorPathTolerance = 1e-4;
// (c) Secular heading drift under equal +/- half periods, as a fraction of the constant-omega yaw
//     rate. Mirror-symmetric switching gives zero up to the tail phase at the switching instants,
//     which is not itself mirror symmetric (measured 1e-4 for the rate, 3e-4 for the total).
constexpr double kMaxRelativeHeadingDrift = 0.01;
// (c) Peak-to-peak heading swing vs the constant-omega prediction |omega_yr| T/2. The yaw rate
//     follows the head spin, which re-establishes within a fraction of a second after a switch,
//     so 5 % (measured 0.9 %).
constexpr double kSwingTolerance = 0.05;
// (c) rms perpendicular residual of the per-period positions about the fitted line, relative to
//     the advance per period (measured 1.2e-3).
constexpr double kLineResidualTolerance = 0.01;
// (c) Net displacement direction vs the period-averaged heading [rad] (measured 5e-4 rad).
constexpr double kNetDirectionTolerance = units::degToRad(1.0);
// (c) Net speed vs the chord prediction built from two mirror-image circular arcs (see test).
//     The arcs assume the constant-omega steady state from the start of each half period, while
//     the tails need ~2 s (a few first-mode relaxation times, see kConstantSteadyFraction) to
//     re-deflect after each switch of a 5 s half period: 15 % (measured -6 %).
constexpr double kNetSpeedTolerance = 0.15;
// (d) With C_yr = 0 the yaw rate must vanish: below 1e-3 of the C_yr = 6 value (measured 4e-8).
constexpr double kNoLateralForceYawRatio = 1e-3;
// (d) Stokes flow is linear in the applied force, and the head spin does not depend on C_yr, so
//     the yaw rate is proportional to C_yr up to the O(omega_yr / omega_t) coupling of the slow
//     turn into the tail deformation: 2 % (measured 4e-5).
constexpr double kLinearInCyrTolerance = 0.02;

const Vec3 kUp(0.0, 1.0, 0.0);  // world vertical of the interface configs (+y, into the air)

std::string configPath(const std::string& file) {
  return std::string(FLAGELLA_CONFIG_DIR) + "/" + file;
}

struct RunResult {
  SimulationConfig config;
  std::vector<TrajectorySample> trajectory;
  SummaryMetrics summary;
  double wall_seconds = 0.0;
};

RunResult simulate(const SimulationConfig& config) {
  RunResult r;
  r.config = config;
  const auto start = std::chrono::steady_clock::now();
  Simulation sim(config);
  sim.run(config.duration);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.trajectory = sim.trajectory();
  r.summary = sim.summary();
  return r;
}

// Interface robot, fitted set, n = 3 with spoke 0 pointing up (spoke_phase 90 deg): the spokes sit
// at 90, 210 and 330 deg, symmetric under the reflection x -> -x through the vertical plane that
// contains the head axis.
SimulationConfig fittedConfig(double omega_rpm, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> overrides{
      "robot.spoke_phase_deg=90", "motor.omega_rpm=" + std::to_string(omega_rpm),
      "simulation.duration=" + std::to_string(kConstantDuration),
      "simulation.steady_fraction=" + std::to_string(kConstantSteadyFraction)};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return loadSimulationConfig(configPath("interface_robot.yaml"), overrides);
}

const RunResult& fittedPlus() {
  static const RunResult run = simulate(fittedConfig(kMotorRpm));
  return run;
}
const RunResult& fittedMinus() {
  static const RunResult run = simulate(fittedConfig(-kMotorRpm));
  return run;
}

// ---- independent post-processing ------------------------------------------------------------

// Horizontal coordinates with (e1, e2, up) right-handed: e1 = +z, e2 = up x e1 = +x.
Eigen::Vector2d horizontal(const Vec3& p) { return {p.z(), p.x()}; }

// Heading psi: azimuth about +up of the forward direction -t^0 (docs/model.md 7.1, omega_yr).
double heading(const TrajectorySample& s) {
  const Eigen::Vector2d f = horizontal(-s.head_axis);
  return std::atan2(f.y(), f.x());
}

std::vector<const TrajectorySample*> window(const std::vector<TrajectorySample>& traj, double t0,
                                            double t1) {
  std::vector<const TrajectorySample*> out;
  for (const TrajectorySample& s : traj)
    if (s.time >= t0 - 1e-9 && s.time <= t1 + 1e-9) out.push_back(&s);
  return out;
}

std::vector<double> unwrappedHeadings(const std::vector<const TrajectorySample*>& w) {
  std::vector<double> psi;
  for (const TrajectorySample* s : w) {
    double a = heading(*s);
    if (!psi.empty()) a = psi.back() + std::remainder(a - psi.back(), 2.0 * M_PI);
    psi.push_back(a);
  }
  return psi;
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double yawRate(const std::vector<const TrajectorySample*>& w) {
  std::vector<double> t;
  for (const TrajectorySample* s : w) t.push_back(s->time);
  return slope(t, unwrappedHeadings(w));
}

struct Circle {
  Eigen::Vector2d center;
  double radius = 0.0;
  double rms = 0.0;  // rms of |p - c| - R
};

// Algebraic (Kasa) least-squares circle: x^2 + y^2 + D x + E y + F = 0.
Circle fitCircle(const std::vector<Eigen::Vector2d>& p) {
  Eigen::MatrixXd A(p.size(), 3);
  Eigen::VectorXd b(p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    A.row(i) << p[i].x(), p[i].y(), 1.0;
    b(i) = -p[i].squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  Circle c;
  c.center = -0.5 * s.head<2>();
  c.radius = std::sqrt(c.center.squaredNorm() - s(2));
  double sum = 0.0;
  for (const Eigen::Vector2d& q : p) sum += std::pow((q - c.center).norm() - c.radius, 2);
  c.rms = std::sqrt(sum / p.size());
  return c;
}

std::vector<Eigen::Vector2d> horizontalPath(const std::vector<const TrajectorySample*>& w) {
  std::vector<Eigen::Vector2d> p;
  for (const TrajectorySample* s : w) p.push_back(horizontal(s->head_position));
  return p;
}

double horizontalPathLength(const std::vector<const TrajectorySample*>& w) {
  double length = 0.0;
  for (size_t i = 1; i < w.size(); ++i)
    length += (horizontal(w[i]->head_position) - horizontal(w[i - 1]->head_position)).norm();
  return length;
}

double relDiff(double a, double b) { return std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

// The sample closest to time t.
const TrajectorySample& sampleAt(const std::vector<TrajectorySample>& traj, double t) {
  return *std::min_element(traj.begin(), traj.end(), [t](const auto& a, const auto& b) {
    return std::abs(a.time - t) < std::abs(b.time - t);
  });
}

double steadyStart(const RunResult& r) { return r.summary.window_start; }
double steadyEnd(const RunResult& r) { return r.summary.window_end; }

// ---- (a) constant omega: steady circling about the vertical ------------------------------------

TEST(InterfaceRobot, CirclesAboutVerticalAtConstantOmega) {
  const RunResult& run = fittedPlus();
  const SummaryMetrics& m = run.summary;
  const double t0 = steadyStart(run), t1 = steadyEnd(run), tm = 0.5 * (t0 + t1);
  const auto all = window(run.trajectory, t0, t1);
  ASSERT_GT(all.size(), 100u);

  const double yaw = yawRate(all);
  const double yaw_first = yawRate(window(run.trajectory, t0, tm));
  const double yaw_second = yawRate(window(run.trajectory, tm, t1));
  const Circle circle = fitCircle(horizontalPath(all));
  const double v_horizontal = horizontalPathLength(all) / (t1 - t0);
  double max_pitch = 0.0;
  for (const TrajectorySample* s : all)
    max_pitch = std::max(max_pitch, std::abs(std::asin(s->head_axis.dot(kUp))));
  const double pitch_rate =
      (std::asin(all.back()->head_axis.dot(kUp)) - std::asin(all.front()->head_axis.dot(kUp))) /
      (t1 - t0);

  std::cout << "[interface +omega] wall " << run.wall_seconds << " s, yaw rate " << yaw
            << " rad/s (summary " << m.yaw_rate << "), halves " << yaw_first << " / " << yaw_second
            << ", R " << circle.radius << " m (summary " << m.circle_radius << "), rms/R "
            << circle.rms / circle.radius << ", v_horizontal/|yaw| " << v_horizontal / std::abs(yaw)
            << " m, omega_h " << m.omega_h << ", omega_t " << m.omega_t << ", max pitch "
            << max_pitch << " rad, pitch rate " << pitch_rate << " rad/s, head height drift "
            << all.back()->head_position.dot(kUp) - all.front()->head_position.dot(kUp) << " m\n";

  // Clearly circling, at a steady rate.
  EXPECT_GT(std::abs(yaw) * (t1 - t0), kMinHeadingTurn);
  EXPECT_LT(relDiff(yaw_first, yaw_second), kSteadyYawTolerance);
  EXPECT_GT(yaw_first * yaw_second, 0.0);
  // The path is a circle of finite radius.
  ASSERT_TRUE(std::isfinite(circle.radius));
  EXPECT_GT(circle.radius, 0.0);
  EXPECT_LT(circle.rms, kCircleRmsTolerance * circle.radius);
  // Uniform circular motion: the heading turns at the rate the velocity does, R = v / omega_yr.
  EXPECT_LT(relDiff(circle.radius, v_horizontal / std::abs(yaw)), kKinematicTolerance);
  // The summary metrics agree with this file's independent post-processing.
  ASSERT_TRUE(m.circle_valid);
  EXPECT_LT(relDiff(m.circle_radius, circle.radius), kSummaryAgreement);
  EXPECT_LT(relDiff(m.yaw_rate, yaw), kSummaryAgreement);
  // The rotation is about the vertical: the head axis stays close to horizontal.
  EXPECT_LT(max_pitch, kMaxPitch);
}

// ---- (b) reversing omega mirrors the circle ---------------------------------------------------
//
// Why mirror symmetry implies equal radii: let P be the reflection x -> -x through the vertical
// plane (y, z) that contains the initial head axis. P maps the robot onto itself (spokes at 90,
// 210, 330 deg), keeps the world vertical +y, and the model's forces are P-covariant: RFT and
// Stokes drag are isotropic, the elastic energies are reflection invariant, and the lateral force
// -C_yr mu0 R L_head (yhat x Omega_h ahat) transforms correctly because Omega_h ahat is an axial
// vector (its z component flips under P). A spin about z changes sense under P, so P maps a
// solution driven at +omega_T onto a solution driven at -omega_T with the same (symmetric) initial
// state. By uniqueness the -omega_T run is the mirror image of the +omega_T run: same radius, same
// speeds, opposite yaw rate.

TEST(InterfaceRobot, ReversingOmegaMirrorsTheCircle) {
  const RunResult& plus = fittedPlus();
  const RunResult& minus = fittedMinus();
  const auto wp = window(plus.trajectory, steadyStart(plus), steadyEnd(plus));
  const auto wm = window(minus.trajectory, steadyStart(minus), steadyEnd(minus));
  const double yaw_p = yawRate(wp), yaw_m = yawRate(wm);
  const Circle cp = fitCircle(horizontalPath(wp)), cm = fitCircle(horizontalPath(wm));

  double max_mirror_error = 0.0;
  ASSERT_EQ(plus.trajectory.size(), minus.trajectory.size());
  for (size_t i = 0; i < plus.trajectory.size(); ++i) {
    Vec3 mirrored = plus.trajectory[i].head_position;
    mirrored.x() = -mirrored.x();
    max_mirror_error =
        std::max(max_mirror_error, (mirrored - minus.trajectory[i].head_position).norm());
  }
  std::cout << "[interface +/-omega] yaw " << yaw_p << " / " << yaw_m << " rad/s, R " << cp.radius
            << " / " << cm.radius << " m (rel diff " << relDiff(cp.radius, cm.radius)
            << "), omega_h " << plus.summary.omega_h_signed << " / " << minus.summary.omega_h_signed
            << ", max mirror path error " << max_mirror_error << " m, wall " << minus.wall_seconds
            << " s\n";

  EXPECT_LT(yaw_p * yaw_m, 0.0) << "reversing the motor must reverse the sense of turning";
  EXPECT_LT(relDiff(std::abs(yaw_p), std::abs(yaw_m)), kMirrorTolerance);
  EXPECT_LT(relDiff(cp.radius, cm.radius), kMirrorTolerance);
  EXPECT_LT(plus.summary.omega_h_signed * minus.summary.omega_h_signed, 0.0);
  EXPECT_LT(relDiff(plus.summary.omega_h, minus.summary.omega_h), kMirrorTolerance);
  EXPECT_LT(max_mirror_error, kMirrorPathTolerance * cp.radius);
}

// ---- (c) binary switching: straight net path ---------------------------------------------------

TEST(InterfaceRobot, BinarySwitchingGivesStraightNetPath) {
  // Path-planning set (docs/model.md 8.3): N = 2, spokes along +/-x (mirror symmetric like above),
  // +/-43.27 rpm with 5 s half periods.
  SimulationConfig binary = loadSimulationConfig(configPath("interface_path_planning.yaml"), {});
  ASSERT_EQ(binary.motor.mode, "binary");
  ASSERT_DOUBLE_EQ(binary.motor.positive_duration, binary.motor.negative_duration);
  const double half = binary.motor.positive_duration;
  const double period = 2.0 * half;
  binary.duration = kBinaryPeriods * period;
  SimulationConfig constant = binary;
  constant.motor.mode = "constant";
  constant.duration = kConstantDuration;
  constant.steady_fraction = kConstantSteadyFraction;

  const RunResult bin = simulate(binary);
  const RunResult cst = simulate(constant);
  const auto wc = window(cst.trajectory, steadyStart(cst), steadyEnd(cst));
  const double yaw_constant = yawRate(wc);
  const Circle circle = fitCircle(horizontalPath(wc));
  // Velocity direction relative to the heading at constant omega (the angle beta in the chord
  // prediction below), from the horizontal head velocity of the raw samples.
  double sin_sum = 0.0, cos_sum = 0.0;
  for (const TrajectorySample* s : wc) {
    const Eigen::Vector2d v = horizontal(s->head_velocity), f = horizontal(-s->head_axis);
    const double beta = std::atan2(f.x() * v.y() - f.y() * v.x(), f.dot(v));
    sin_sum += std::sin(beta);
    cos_sum += std::cos(beta);
  }
  const double beta = std::atan2(sin_sum, cos_sum);

  // Heading and position at the start of every whole period after the first (k = 1..K).
  std::vector<double> times, psi;
  std::vector<Eigen::Vector2d> positions;
  {
    std::vector<const TrajectorySample*> at;
    for (int k = 1; k <= kBinaryPeriods; ++k) at.push_back(&sampleAt(bin.trajectory, k * period));
    psi = unwrappedHeadings(at);
    for (const TrajectorySample* s : at) {
      times.push_back(s->time);
      positions.push_back(horizontal(s->head_position));
    }
  }
  const double drift_rate = slope(times, psi);
  const double drift_total = psi.back() - psi.front();

  // Heading swing within the periods and the period-averaged heading.
  const auto wb = window(bin.trajectory, period, kBinaryPeriods * period);
  const std::vector<double> psi_all = unwrappedHeadings(wb);
  const auto [psi_min, psi_max] = std::minmax_element(psi_all.begin(), psi_all.end());
  const double swing = *psi_max - *psi_min;
  double mean_sin = 0.0, mean_cos = 0.0;
  for (double a : psi_all) {
    mean_sin += std::sin(a);
    mean_cos += std::cos(a);
  }
  const double mean_heading = std::atan2(mean_sin, mean_cos);

  // Straight line through the per-period positions (principal direction).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : positions) centroid += p;
  centroid /= positions.size();
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : positions) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  Eigen::Vector2d direction = eig.eigenvectors().col(1);
  const Eigen::Vector2d net = positions.back() - positions.front();
  if (direction.dot(net) < 0.0) direction = -direction;
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  double residual = 0.0;
  for (const auto& p : positions) residual += std::pow((p - centroid).dot(normal), 2);
  residual = std::sqrt(residual / positions.size());
  const double elapsed = times.back() - times.front();
  const double advance_per_period = net.norm() / (kBinaryPeriods - 1);
  const double net_speed = net.norm() / elapsed;
  const double net_direction = std::atan2(net.y(), net.x());

  // Chord prediction: during a half period the head runs along a circular arc of radius R turning
  // the heading by Delta = |omega_yr| T/2, chord 2 R sin(Delta/2); its velocity makes the angle
  // beta with the heading. The next half period is the mirror image (section (b)): the same chord
  // length, the heading turning back, and the velocity at -beta. The two chords' components
  // across the mean heading cancel, and along it they add to 2 * 2 R sin(Delta/2) cos(beta) per
  // period.
  const double delta = std::abs(yaw_constant) * half;
  const double predicted_speed =
      4.0 * circle.radius * std::sin(0.5 * delta) * std::cos(beta) / period;

  std::cout << "[interface binary] wall " << bin.wall_seconds << " + " << cst.wall_seconds
            << " s; constant yaw " << yaw_constant << " rad/s, R " << circle.radius << " m, beta "
            << beta << " rad; binary heading drift " << drift_total << " rad over " << elapsed
            << " s (rate " << drift_rate << " rad/s, constant-omega turn over the same time "
            << yaw_constant * elapsed << " rad); swing " << swing << " rad (predicted " << delta
            << "); net speed " << net_speed << " m/s (chord prediction " << predicted_speed
            << ", summary net_speed " << bin.summary.net_speed << "); line residual/advance "
            << residual / advance_per_period << "; net direction " << net_direction
            << " vs mean heading " << mean_heading << " rad\n";

  // No secular heading drift, in contrast to the constant-omega run.
  EXPECT_LT(std::abs(drift_rate), kMaxRelativeHeadingDrift * std::abs(yaw_constant));
  EXPECT_LT(std::abs(drift_total), kMaxRelativeHeadingDrift * std::abs(yaw_constant) * elapsed);
  // The heading oscillates by about the constant-omega turn of one half period.
  EXPECT_NEAR(swing, delta, kSwingTolerance * delta);
  // Whole-period positions lie on a straight line, with a non-zero net advance along it.
  EXPECT_LT(residual, kLineResidualTolerance * advance_per_period);
  EXPECT_GT(net_speed, 0.0);
  EXPECT_NEAR(net_speed, predicted_speed, kNetSpeedTolerance * predicted_speed);
  // The straight chord follows the mean heading (or runs against it if |beta| > 90 deg).
  const double expected_direction = mean_heading + (std::cos(beta) < 0.0 ? M_PI : 0.0);
  EXPECT_LT(std::abs(std::remainder(net_direction - expected_direction, 2.0 * M_PI)),
            kNetDirectionTolerance);
}

// ---- (d) the lateral head force causes the circling -------------------------------------------

TEST(InterfaceRobot, NoLateralForceNoCircling) {
  const RunResult& with = fittedPlus();
  const RunResult without =
      simulate(fittedConfig(kMotorRpm, {"effects.interface_lateral_force.C_yr=0"}));
  const RunResult half =
      simulate(fittedConfig(kMotorRpm, {"effects.interface_lateral_force.C_yr=3"}));
  const auto ww = window(with.trajectory, steadyStart(with), steadyEnd(with));
  const auto wo = window(without.trajectory, steadyStart(without), steadyEnd(without));
  const auto wh = window(half.trajectory, steadyStart(half), steadyEnd(half));
  const double yaw_with = yawRate(ww), yaw_without = yawRate(wo), yaw_half = yawRate(wh);
  const std::vector<double> psi = unwrappedHeadings(window(without.trajectory, 0.0, 1e9));
  const auto [lo, hi] = std::minmax_element(psi.begin(), psi.end());
  std::cout << "[interface C_yr] yaw rate C_yr=6: " << yaw_with << ", C_yr=3: " << yaw_half
            << ", C_yr=0: " << yaw_without << " rad/s; heading range without " << *hi - *lo
            << " rad; speed without " << without.summary.speed << " m/s; wall "
            << without.wall_seconds << " + " << half.wall_seconds << " s\n";

  EXPECT_LT(std::abs(yaw_without), kNoLateralForceYawRatio * std::abs(yaw_with));
  EXPECT_LT(*hi - *lo, kNoLateralForceYawRatio * std::abs(yaw_with) * kConstantDuration);
  // Without circling the robot swims straight along its axis (head first, -z).
  EXPECT_GT(without.summary.speed, 0.0);
  // The turning is proportional to the lateral coefficient (same sense, half the rate).
  EXPECT_GT(yaw_half * yaw_with, 0.0);
  EXPECT_NEAR(yaw_half, 0.5 * yaw_with, kLinearInCyrTolerance * std::abs(0.5 * yaw_with));
}

}  // namespace
}  // namespace flagella
