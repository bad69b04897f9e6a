#include "flagella_control/steering_calibration_runner.h"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "calibration_steps.h"
#include "flagella_control/head_attitude.h"
#include "flagella_control/heading.h"
#include "flagella_control/session_driver.h"
#include "flagella_control/validation.h"
#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella::control {

namespace {

const char* const kOptions = "steering calibration options";

using calibration_steps::advance;
using calibration_steps::attitudeOf;
using calibration_steps::elevationRateOver;
using calibration_steps::headPosition;

}  // namespace

void SteeringCalibrationOptions::validate() const {
  requireInRange(kOptions, "threshold_rpm", threshold_rpm, 0.0, 1e3);
  requirePositive(kOptions, "threshold_run", threshold_run, "s");
  flagella::validate(search);
  requireInRange(kOptions, "cruise_fraction", cruise_fraction, 0.05, 0.99);
  requireInRange(kOptions, "pulse_factor", pulse_factor, 1.01, 20.0);
  requirePositive(kOptions, "pulse_duration", pulse_duration, "s");
  requireInRange(kOptions, "relax_duration", relax_duration, 0.0, 600.0);
  requireInRange(kOptions, "lead_duration", lead_duration, 0.0, 600.0);
  if (pulses < 3 || pulses > 1000)
    throw std::invalid_argument("steering calibration options: pulses must be in [3, 1000], got " +
                                std::to_string(pulses));
  requireInRange(kOptions, "settle_time", settle_time, 0.0, 1e4);
  requirePositive(kOptions, "window", window, "s");
  requireInRange(kOptions, "after_cycle", after_cycle, 0.0, 600.0);
  requirePositive(kOptions, "cruise_measure", cruise_measure, "s");
  requireInRange(kOptions, "slider_step", slider_step, 1e-5, 0.05);
  requirePositive(kOptions, "pitch_window", pitch_window, "s");
  requireInRange(kOptions, "crab_step", crab_step, 1e-7, 1e-3);
  requireInRange(kOptions, "crab_settle", crab_settle, 0.0, 1e4);
  requirePositive(kOptions, "crab_measure", crab_measure, "s");
  if (slider_pulses < 0 || slider_pulses > 1000)
    throw std::invalid_argument(
        "steering calibration options: slider_pulses must be in [0, 1000], got " +
        std::to_string(slider_pulses));
  requireInRange(kOptions, "cycle_slider_step", cycle_slider_step, 1e-7, 1e-2);
}

double measureCrab(const flagella::SimulationConfig& config, double cruise_omega, double slider,
                   double settle, double measure) {
  SessionDriver driver(config, cruise_omega, "crab");
  driver.commandSlider(slider);
  Vec3 axis = Vec3::Zero();
  double shaft = 0.0;
  const auto cruise = [&](double) { return cruise_omega; };
  advance(driver, settle, cruise, axis, shaft);
  const Vec3 start = headPosition(driver);
  axis.setZero();
  advance(driver, measure, cruise, axis, shaft);
  const Vec3 moved = headPosition(driver) - start;
  return wrapAngle(azimuthOf(moved) - azimuthOf(axis));
}

void fitPhaseLaw(const std::vector<PulseObservation>& pulses, BuckleSchedule& schedule) {
  if (pulses.size() < 3)
    throw std::invalid_argument("phase law: needs at least 3 pulses, got " +
                                std::to_string(pulses.size()));
  const long n = static_cast<long>(pulses.size());
  double best = INFINITY;
  for (double roll_sign : {1.0, -1.0}) {
    for (double shaft_sign : {1.0, -1.0}) {
      // up = b_u + A cos(phi) - B sin(phi), left = b_l + A sin(phi) + B cos(phi)
      Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n, 4);
      Eigen::VectorXd y(2 * n);
      for (long i = 0; i < n; ++i) {
        const PulseObservation& p = pulses[i];
        const double phi = roll_sign * p.roll + shaft_sign * p.shaft;
        M.row(2 * i) << 1.0, 0.0, std::cos(phi), -std::sin(phi);
        M.row(2 * i + 1) << 0.0, 1.0, std::sin(phi), std::cos(phi);
        y(2 * i) = p.up;
        y(2 * i + 1) = p.left;
      }
      const Eigen::VectorXd x = M.colPivHouseholderQr().solve(y);
      const double rms = std::sqrt((y - M * x).squaredNorm() / n);
      if (rms < best) {
        best = rms;
        schedule.roll_sign = roll_sign;
        schedule.shaft_sign = shaft_sign;
        schedule.bias_up = x(0);
        schedule.bias_left = x(1);
        schedule.deflection = std::hypot(x(2), x(3));
        schedule.phase_offset = wrapAngle(std::atan2(x(3), x(2)));
        schedule.phase_spread = rms;
      }
    }
  }
}

void fitSliderTurn(const std::vector<PulseObservation>& plus,
                   const std::vector<PulseObservation>& minus, double step,
                   BuckleSchedule& schedule) {
  if (plus.empty() || minus.empty() || !(step > 0.0))
    throw std::invalid_argument("slider turn: needs pulses at both offsets and a step > 0");
  // Mean residual of the phase law (fitted at park) over one side's cycles.
  const auto residual = [&](const std::vector<PulseObservation>& pulses, double& up, double& left) {
    up = left = 0.0;
    for (const PulseObservation& p : pulses) {
      double pu = 0.0, pl = 0.0;
      schedule.predictedTurn(p.roll, p.shaft, pu, pl);
      up += (p.up - pu) / pulses.size();
      left += (p.left - pl) / pulses.size();
    }
  };
  double up_plus, left_plus, up_minus, left_minus;
  residual(plus, up_plus, left_plus);
  residual(minus, up_minus, left_minus);
  schedule.up_per_slider = (up_plus - up_minus) / (2.0 * step);
  schedule.left_per_slider = (left_plus - left_minus) / (2.0 * step);
}

std::vector<PulseObservation> observePulses(const flagella::SimulationConfig& config,
                                            const BuckleSchedule& schedule, double cruise_omega,
                                            const SteeringCalibrationOptions& options, int count,
                                            double cycle_offset) {
  SessionDriver driver(config, schedule.pulse_omega,
                       std::string("pulses (") + scheduleName(schedule.kind) + ")");
  const double rest = config.slider.enabled ? config.slider.initial_position : 0.0;
  const auto cruise = [&](double) { return cruise_omega; };
  Vec3 sum = Vec3::Zero();
  double shaft = 0.0;
  advance(driver, options.settle_time, cruise, sum, shaft);
  sum.setZero();
  advance(driver, options.window, cruise, sum, shaft);
  std::vector<PulseObservation> pulses;
  for (int i = 0; i < count; ++i) {
    const Vec3 before = sum.normalized();
    PulseObservation p;
    p.roll = attitudeOf(driver).roll;
    p.shaft = shaft;
    Vec3 ignored = Vec3::Zero();
    if (cycle_offset != 0.0) driver.commandSlider(rest + cycle_offset);
    advance(
        driver, schedule.cycleDuration(),
        [&](double s) { return schedule.omegaAt(s, cruise_omega); }, ignored, shaft);
    if (cycle_offset != 0.0) driver.commandSlider(rest);
    advance(driver, options.after_cycle, cruise, ignored, shaft);
    sum.setZero();
    advance(driver, options.window, cruise, sum, shaft);
    const Vec3 after = sum.normalized();
    // chi in the plane normal to the direction of travel before (head_attitude.h).
    const NormalPlane plane = normalPlane(before);
    const Vec3 change = after - before;
    p.up = change.dot(plane.u);
    p.left = change.dot(plane.w);
    pulses.push_back(p);
  }
  return pulses;
}

namespace {

using ProgressReport = std::function<void(const std::string&)>;

// Step 1: the buckling threshold [rpm], given or searched; notes how it was found in `source`.
double findThresholdRpm(const flagella::SimulationConfig& config,
                        const SteeringCalibrationOptions& options, std::ostringstream& source) {
  double threshold_rpm = options.threshold_rpm;
  if (threshold_rpm > 0.0) {
    source << "threshold given " << threshold_rpm << " rpm; ";
  } else {
    flagella::SimulationConfig probe_config = config;
    probe_config.duration = options.threshold_run;
    const flagella::ThresholdResult r = flagella::findThreshold(
        [&](double rpm) { return flagella::runBucklingProbe(probe_config, rpm); }, options.search);
    if (!r.found) throw std::runtime_error("steering calibration: threshold search: " + r.message);
    threshold_rpm = r.threshold;
    source << "threshold " << options.threshold_run << " s runs, " << r.runs.size() << " runs; ";
  }
  return threshold_rpm;
}

// Step 2: the cruise speed at c.cruise_omega [m/s] (net head displacement over cruise_measure).
double measureCruiseSpeed(const flagella::SimulationConfig& config,
                          const SteeringCalibrationOptions& options, const SteeringCalibration& c) {
  SessionDriver driver(config, c.cruise_omega, "cruise");
  Vec3 ignored = Vec3::Zero();
  double shaft = 0.0;
  const auto cruise = [&](double) { return c.cruise_omega; };
  advance(driver, options.settle_time, cruise, ignored, shaft);
  const Vec3 start = headPosition(driver);
  advance(driver, options.cruise_measure, cruise, ignored, shaft);
  return (headPosition(driver) - start).norm() / options.cruise_measure;
}

// The progress line describing one fitted buckle schedule.
std::string describeSchedule(const BuckleSchedule& schedule) {
  const double deg = 180 / M_PI;
  return std::string(scheduleName(schedule.kind)) + ": per cycle, constant turn (up " +
         numberString(schedule.bias_up * deg) + ", left " + numberString(schedule.bias_left * deg) +
         ") deg plus " + numberString(schedule.deflection * deg) + " deg by phase; residual " +
         numberString(schedule.phase_spread * deg) + " deg; per um of slider held through " +
         "the cycle (up " + numberString(schedule.up_per_slider * 1e-6 * deg) + ", left " +
         numberString(schedule.left_per_slider * 1e-6 * deg) + ") deg";
}

// Step 3: sets up the relax and three-level schedules and fits their phase law and slider turn.
void calibrateSchedules(const flagella::SimulationConfig& config,
                        const SteeringCalibrationOptions& options, SteeringCalibration& c,
                        const ProgressReport& report) {
  const double pulse_omega = options.pulse_factor * c.buckling_threshold;
  c.relax.kind = BuckleScheduleKind::Relax;
  c.relax.pulse_omega = pulse_omega;
  c.relax.pulse_duration = options.pulse_duration;
  c.relax.relax_duration = options.relax_duration;
  c.three_level.kind = BuckleScheduleKind::ThreeLevel;
  c.three_level.lead_duration = options.lead_duration;
  c.three_level.pulse_omega = pulse_omega;
  c.three_level.pulse_duration = options.pulse_duration;
  for (BuckleSchedule* schedule : {&c.relax, &c.three_level}) {
    fitPhaseLaw(observePulses(config, *schedule, c.cruise_omega, options, options.pulses),
                *schedule);
    if (options.slider_pulses > 0 && config.slider.enabled) {
      const double step = options.cycle_slider_step;
      fitSliderTurn(
          observePulses(config, *schedule, c.cruise_omega, options, options.slider_pulses, step),
          observePulses(config, *schedule, c.cruise_omega, options, options.slider_pulses, -step),
          step, *schedule);
    }
    report(describeSchedule(*schedule));
  }
}

// The slider's park position: no couple at the nominal l_0 (docs/model.md 5: l = l_0 + (m_s / m_h)
// x_s = 0). Checked before any run: it and the pitch-rate step must lie within the travel.
double parkPosition(const flagella::SimulationConfig& config,
                    const SteeringCalibrationOptions& options) {
  const flagella::Simulation sim(config);
  const double ratio = config.slider.mass / sim.parameter("effects.com_offset.head_mass");
  const double l0 =
      sim.parameter("effects.com_offset.offset") - ratio * config.slider.initial_position;
  const double park = -l0 / ratio;
  const double min = config.slider.travel_min, max = config.slider.travel_max;
  if (!(park >= min && park + options.slider_step <= max))
    throw std::invalid_argument(
        "slider: the park position (no couple: -l_0 m_h / m_s = " + numberString(park * 1e3) +
        " mm) and the calibration's step of " + numberString(options.slider_step * 1e3) +
        " mm after it must lie within slider.travel_min .. travel_max [" + numberString(min * 1e3) +
        ", " + numberString(max * 1e3) + "] mm (set by effects.com_offset.offset and slider.mass)");
  return park;
}

// Step 4: the slider's pitch rate per metre from the park position (c.park_position).
void calibrateSlider(const flagella::SimulationConfig& config,
                     const SteeringCalibrationOptions& options, SteeringCalibration& c,
                     const ProgressReport& report) {
  SessionDriver driver(config, c.cruise_omega, "slider step");
  const double stepped = c.park_position + options.slider_step;
  driver.commandSlider(c.park_position);
  Vec3 ignored = Vec3::Zero();
  double shaft = 0.0;
  const auto cruise = [&](double) { return c.cruise_omega; };
  advance(driver, options.settle_time, cruise, ignored, shaft);
  // The robot's own pitching at park, over a whole window (the head wobbles with the
  // flagellum's turn).
  c.park_pitch_rate = elevationRateOver(driver, options.window, c.cruise_omega);
  driver.commandSlider(stepped);
  const double slope = elevationRateOver(driver, options.pitch_window, c.cruise_omega);
  c.pitch_rate_per_slider = slope / (stepped - c.park_position);
  report("slider: park " + numberString(c.park_position * 1e3) + " mm, pitch rate " +
         numberString(c.pitch_rate_per_slider * 1e-3 * 180 / M_PI) + " deg/s per mm; at park " +
         numberString(c.park_pitch_rate * 180 / M_PI) + " deg/s");
}

// Step 5: the crab angle per slider metre, parked a few micrometres to either side of park.
void calibrateCrab(const flagella::SimulationConfig& config,
                   const SteeringCalibrationOptions& options, SteeringCalibration& c,
                   const ProgressReport& report) {
  const auto crabAt = [&](double offset) {
    return measureCrab(config, c.cruise_omega,
                       std::clamp(c.park_position + offset, c.slider_min, c.slider_max),
                       options.crab_settle, options.crab_measure);
  };
  const double plus = crabAt(options.crab_step), minus = crabAt(-options.crab_step);
  c.crab_per_slider = (plus - minus) / (2.0 * options.crab_step);
  const double deg = 180 / M_PI;
  report("crab: " + numberString(minus * deg) + " / " + numberString(plus * deg) + " deg at -+" +
         numberString(options.crab_step * 1e6) + " um of slider, " +
         numberString(c.crab_per_slider * 1e-6 * deg) + " deg per um");
}

}  // namespace

SteeringCalibration calibrateSteering(const flagella::SimulationConfig& config,
                                      const SteeringCalibrationOptions& options,
                                      const std::function<void(const std::string&)>& progress) {
  options.validate();
  if (!config.slider.enabled)
    throw std::invalid_argument(
        "steering calibration: the config has no slider: section (the mass-transformer's "
        "internal mass, with effects.com_offset; config/helical_steering_source.yaml has one)");
  const ProgressReport report = [&](const std::string& line) {
    if (progress) progress(line);
  };
  SteeringCalibration c;
  std::ostringstream source;
  source << config.source << "; ";
  c.slider_min = config.slider.travel_min;
  c.slider_max = config.slider.travel_max;
  c.park_position = parkPosition(config, options);
  // 1. Buckling threshold.
  const double threshold_rpm = findThresholdRpm(config, options, source);
  c.buckling_threshold = flagella::units::rpmToRadPerSec(threshold_rpm);
  c.cruise_omega = options.cruise_fraction * c.buckling_threshold;
  report("buckling threshold " + numberString(threshold_rpm) + " rpm, cruise " +
         numberString(options.cruise_fraction * threshold_rpm) + " rpm");
  // 2. Cruise speed.
  c.cruise_speed = measureCruiseSpeed(config, options, c);
  report("cruise speed " + numberString(c.cruise_speed * 1e3) + " mm/s");
  // 3. The two buckle schedules.
  calibrateSchedules(config, options, c, report);
  // 4. Slider: pitch rate per metre from the park position.
  calibrateSlider(config, options, c, report);
  // 5. Crab angle per slider metre: parked a few micrometres to either side (docs/model.md 7.4).
  calibrateCrab(config, options, c, report);
  source << "cruise " << options.cruise_fraction << " omega_b, pulses " << options.pulse_factor
         << " omega_b for " << options.pulse_duration << " s, " << options.pulses
         << " per schedule, windows " << options.window << " s, crab at +-"
         << options.crab_step * 1e6 << " um over " << options.crab_measure << " s";
  c.source = source.str();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("steering calibration is unusable: ") + e.what());
  }
  return c;
}

}  // namespace flagella::control
