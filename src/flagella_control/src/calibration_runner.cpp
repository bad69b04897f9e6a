#include "flagella_control/calibration_runner.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_control/heading.h"
#include "flagella_control/session_driver.h"
#include "flagella_control/validation.h"
#include "flagella_sim/outputs/fits.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella::control {

namespace {

const char* const kOptions = "calibration options";

/// Number of steps of length dt in `duration`, which must be a whole number of steps.
long wholeSteps(const std::string& field, double duration, double dt) {
  const double n = std::round(duration / dt);
  if (n < 1.0 || std::abs(n * dt - duration) > 1e-6 * dt)
    throw std::invalid_argument(
        "calibration options: " + field + " = " + numberString(duration) +
        " s must be a whole, non-zero number of time steps dt = " + numberString(dt) + " s");
  return static_cast<long>(n);
}

/// Head position (x, y) and heading in the output frame.
void measure(const SessionDriver& driver, Eigen::Vector2d& xy, double& psi) {
  const flagella::RodSnapshot s = driver.session().snapshot();
  const Eigen::Quaterniond& q = s.head_orientation;
  const double quaternion[4] = {q.x(), q.y(), q.z(), q.w()};
  xy = s.head_position.head<2>();
  psi = headingFromQuaternion(quaternion);
  if (!xy.allFinite() || !std::isfinite(psi))
    throw std::runtime_error("calibration " + driver.run() + ": non-finite head state at t = " +
                             numberString(driver.time()) + " s");
}

Eigen::Vector2d rotate(const Eigen::Vector2d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

}  // namespace

void CalibrationOptions::validate() const {
  if (!std::isfinite(omega) || omega < 0.0)
    throw std::invalid_argument(
        "calibration options: omega must be >= 0 rad/s (0: from the "
        "config), got " +
        numberString(omega));
  requirePositive(kOptions, "switch_period", switch_period, "s");
  if (!std::isfinite(settle_time) || settle_time < 0.0)
    throw std::invalid_argument("calibration options: settle_time must be >= 0 s, got " +
                                numberString(settle_time));
  requirePositive(kOptions, "measure_time", measure_time, "s");
  requirePositive(kOptions, "sample_interval", sample_interval, "s");
  if (measure_time < 4.0 * sample_interval)
    throw std::invalid_argument(
        "calibration options: measure_time = " + numberString(measure_time) +
        " s must span at least 4 sample intervals of " + numberString(sample_interval) + " s");
  if (settle_periods < 0)
    throw std::invalid_argument("calibration options: settle_periods must be >= 0, got " +
                                std::to_string(settle_periods));
  if (measure_periods < 1)
    throw std::invalid_argument("calibration options: measure_periods must be >= 1, got " +
                                std::to_string(measure_periods));
}

double calibrationOmega(const flagella::SimulationConfig& config,
                        const CalibrationOptions& options) {
  const double omega = options.omega > 0.0 ? options.omega : std::abs(config.motor.omega);
  if (!(omega > 0.0) || !std::isfinite(omega))
    throw std::invalid_argument(
        "calibration options: omega is 0 and the config's motor.omega_rpm is 0 too");
  return omega;
}

SignResponse measureSignResponse(const flagella::SimulationConfig& config, double signed_omega,
                                 const CalibrationOptions& options) {
  options.validate();
  const std::string run = std::string("constant ") + (signed_omega > 0 ? "+" : "-") + "omega";
  SessionDriver driver(config, std::abs(signed_omega), run);
  const double dt = driver.dt();
  const long settle_steps = std::lround(options.settle_time / dt);
  const long sample_steps = wholeSteps("sample_interval", options.sample_interval, dt);
  const long samples = std::lround(options.measure_time / options.sample_interval) + 1;
  const double h = sample_steps * dt;  // exact sample spacing

  for (long k = 0; k < settle_steps; ++k) driver.step(signed_omega);
  std::vector<double> t, psi;
  std::vector<Eigen::Vector2d> xy;
  for (long i = 0; i < samples; ++i) {
    if (i > 0)
      for (long k = 0; k < sample_steps; ++k) driver.step(signed_omega);
    Eigen::Vector2d p;
    double heading;
    measure(driver, p, heading);
    t.push_back(driver.time());
    xy.push_back(p);
    psi.push_back(heading);
  }

  SignResponse r;
  const std::vector<double> unwrapped = flagella::unwrapAngles(psi);
  r.yaw_rate = flagella::fitLine(t, unwrapped).slope;
  const flagella::CircleFit circle = flagella::fitCircle(xy);
  if (!circle.valid || !std::isfinite(circle.radius))
    throw std::runtime_error("calibration " + run +
                             ": circle fit of the head path is invalid (path too straight or "
                             "too short: increase measure_time)");
  r.circle_radius = circle.radius;

  // Central differences at the interior samples.
  double speed = 0.0;
  Eigen::Vector2d body = Eigen::Vector2d::Zero();
  std::vector<double> angles;
  for (std::size_t i = 1; i + 1 < xy.size(); ++i) {
    const Eigen::Vector2d v = (xy[i + 1] - xy[i - 1]) / (2.0 * h);
    speed += v.norm();
    body += rotate(v, -psi[i]);
    angles.push_back(wrapAngle(std::atan2(v.y(), v.x()) - psi[i]));
  }
  const double n = static_cast<double>(angles.size());
  r.speed = speed / n;
  body /= n;
  r.body_velocity[0] = body.x();
  r.body_velocity[1] = body.y();
  // Mean angle, taken relative to the direction of the mean body velocity so that a mean near
  // +-pi does not average +pi and -pi to 0.
  const double reference = std::atan2(body.y(), body.x());
  double offset = 0.0;
  for (const double a : angles) offset += wrapAngle(a - reference);
  r.axis_path_angle = wrapAngle(reference + offset / n);

  for (const double x : {r.yaw_rate, r.circle_radius, r.speed, r.axis_path_angle})
    if (!std::isfinite(x))
      throw std::runtime_error("calibration " + run + ": non-finite measurement");
  return r;
}

SwitchingResponse measureSwitching(const flagella::SimulationConfig& config, double omega,
                                   const CalibrationOptions& options) {
  options.validate();
  const std::string run = "periodic switching";
  SessionDriver driver(config, omega, run);
  const double dt = driver.dt();
  const long half_steps = wholeSteps("switch_period/2", 0.5 * options.switch_period, dt);
  const long sample_steps = wholeSteps("sample_interval", options.sample_interval, dt);
  const long period_steps = 2 * half_steps;
  const long first = options.settle_periods * period_steps;
  const long last = (options.settle_periods + options.measure_periods) * period_steps;

  // The heading is followed at every sample and at every period start, so that it can be
  // unwrapped across periods whatever T is (it turns far less than pi per sample).
  std::vector<Eigen::Vector2d> start_xy;
  std::vector<double> start_psi;  // unwrapped
  double psi_unwrapped = 0.0, psi_last = 0.0;
  bool have_heading = false;
  for (long k = 0; k <= last; ++k) {
    const bool period_start = k >= first && (k - first) % period_steps == 0;
    if (period_start || k % sample_steps == 0) {
      Eigen::Vector2d p;
      double psi;
      measure(driver, p, psi);
      psi_unwrapped = have_heading ? psi_unwrapped + wrapAngle(psi - psi_last) : psi;
      psi_last = psi;
      have_heading = true;
      if (period_start) {
        start_xy.push_back(p);
        start_psi.push_back(psi_unwrapped);
      }
    }
    if (k == last) break;
    driver.step((k / half_steps) % 2 == 0 ? omega : -omega);
  }

  SwitchingResponse r;
  const std::size_t periods = start_xy.size() - 1;
  std::vector<Eigen::Vector2d> local;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < periods; ++i) {
    local.push_back(rotate(start_xy[i + 1] - start_xy[i], -start_psi[i]));
    mean += local.back();
  }
  mean /= static_cast<double>(periods);
  double spread = 0.0;
  for (const Eigen::Vector2d& d : local) spread += (d - mean).squaredNorm();
  r.advance_per_period = mean.norm();
  r.advance_angle = std::atan2(mean.y(), mean.x());
  r.heading_drift_per_period = (start_psi.back() - start_psi.front()) / periods;
  r.displacement_spread = std::sqrt(spread / periods);
  if (!std::isfinite(r.advance_per_period) || !std::isfinite(r.heading_drift_per_period))
    throw std::runtime_error("calibration " + run + ": non-finite measurement");
  return r;
}

BinaryCalibration calibrate(const flagella::SimulationConfig& config,
                            const CalibrationOptions& options) {
  options.validate();
  // Fail before minutes of simulation, not after.
  wholeSteps("switch_period/2", 0.5 * options.switch_period, config.dt);
  wholeSteps("sample_interval", options.sample_interval, config.dt);
  BinaryCalibration c;
  c.omega = calibrationOmega(config, options);
  c.switch_period = options.switch_period;
  c.plus = measureSignResponse(config, +c.omega, options);
  c.minus = measureSignResponse(config, -c.omega, options);
  const SwitchingResponse s = measureSwitching(config, c.omega, options);
  c.advance_per_period = s.advance_per_period;
  c.advance_angle = s.advance_angle;
  c.heading_drift_per_period = s.heading_drift_per_period;
  std::ostringstream source;
  source << config.source << "; constant sign: settle " << options.settle_time << " s, measure "
         << options.measure_time << " s, sample " << options.sample_interval << " s; switching: T "
         << options.switch_period << " s, settle " << options.settle_periods << " + measure "
         << options.measure_periods << " periods";
  c.source = source.str();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("calibration result is unusable: ") + e.what());
  }
  return c;
}

}  // namespace flagella::control
