#include "flagella_control/steering_response_tables.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "calibration_steps.h"
#include "flagella_control/heading.h"
#include "flagella_control/validation.h"

namespace flagella::control {

namespace {

const char* const kTable = "steering table options";
constexpr double kDeg = 180.0 / M_PI;

using calibration_steps::advance;
using calibration_steps::attitudeOf;
using calibration_steps::elevationRateOver;

// Steps at the cruise until `reached(elevation)`; returns the time taken, or -1 after `timeout`.
// Each step's direction of travel goes to `hold` (if given) at the time since the call.
double timeUntil(SessionDriver& driver, double cruise_omega, double timeout,
                 const std::function<bool(double)>& reached, HeldAttitudeWindow* hold = nullptr) {
  const long steps = std::lround(timeout / driver.dt());
  for (long k = 1; k <= steps; ++k) {
    driver.step(cruise_omega);
    const Vec3 forward = attitudeOf(driver).forward;
    if (hold) hold->add(k * driver.dt(), forward);
    if (reached(elevationOf(forward))) return k * driver.dt();
  }
  return -1.0;
}

}  // namespace

void HeldAttitudeWindow::add(double t, const Vec3& forward) {
  double azimuth = azimuthOf(forward);
  // unwrapped: the nearest turn of the previous sample's azimuth
  if (!samples_.empty())
    azimuth = samples_.back().azimuth + wrapAngle(azimuth - samples_.back().azimuth);
  else
    first_ = azimuth;
  samples_.push_back({t, elevationOf(forward), azimuth});
  while (samples_.front().t < t - window_) samples_.pop_front();
}

void HeldAttitudeWindow::fit(double& elevation, double& elevation_rate,
                             double& azimuth_rate) const {
  elevation = elevation_rate = azimuth_rate = 0.0;
  if (samples_.size() < 2) return;
  calibration_steps::SlopeFit elevation_fit, azimuth_fit;
  for (const Sample& s : samples_) {
    elevation += s.elevation / static_cast<double>(samples_.size());
    elevation_fit.add(s.t, s.elevation);
    azimuth_fit.add(s.t, s.azimuth);
  }
  elevation_rate = elevation_fit.slope();
  azimuth_rate = azimuth_fit.slope();
}

void SteeringTableOptions::validate() const {
  for (double f : pulse_factors) requireInRange(kTable, "pulse_factors", f, 1.0 + 1e-9, 20.0);
  for (double d : pulse_durations) requireInRange(kTable, "pulse_durations", d, 1e-3, 600.0);
  if (pulse_factors.empty() != pulse_durations.empty())
    throw std::invalid_argument(std::string(kTable) +
                                ": pulse_factors and pulse_durations are given together");
  for (double x : slider_offsets) {
    requireInRange(kTable, "slider_offsets", std::abs(x), 1e-7, 0.05);
  }
  requireInRange(kTable, "flip_elevation", flip_elevation, 1e-3, M_PI / 2 - 1e-3);
  requirePositive(kTable, "flip_timeout", flip_timeout, "s");
  requireInRange(kTable, "hold_window", hold_window, 1e-3, 600.0);
}

std::vector<BuckleTurnRow> measureBuckleTurnTable(
    const flagella::SimulationConfig& config, const SteeringCalibration& calibration,
    const SteeringTableOptions& table, const SteeringCalibrationOptions& options,
    const std::function<void(const std::string&)>& progress) {
  table.validate();
  std::vector<BuckleTurnRow> rows;
  for (double factor : table.pulse_factors) {
    for (double duration : table.pulse_durations) {
      BuckleTurnRow row;
      row.pulse_factor = factor;
      row.pulse_duration = duration;
      row.relax = calibration.relax;
      row.three_level = calibration.three_level;
      for (BuckleSchedule* s : {&row.relax, &row.three_level}) {
        s->pulse_omega = factor * calibration.buckling_threshold;
        s->pulse_duration = duration;
        fitPhaseLaw(observePulses(config, *s, calibration.cruise_omega, options, options.pulses),
                    *s);
      }
      rows.push_back(row);
      if (progress)
        progress("turn table: " + std::to_string(factor) + " omega_b for " +
                 std::to_string(duration) + " s: relax " +
                 std::to_string(row.relax.deflection * kDeg) + " deg (residual " +
                 std::to_string(row.relax.phase_spread * kDeg) + "), three_level " +
                 std::to_string(row.three_level.deflection * kDeg) + " deg (residual " +
                 std::to_string(row.three_level.phase_spread * kDeg) + ")");
    }
  }
  return rows;
}

std::vector<SliderResponseRow> measureSliderTable(
    const flagella::SimulationConfig& config, const SteeringCalibration& calibration,
    const SteeringTableOptions& table, const SteeringCalibrationOptions& options,
    const std::function<void(const std::string&)>& progress) {
  table.validate();
  std::vector<SliderResponseRow> rows;
  const double cruise = calibration.cruise_omega;
  for (double offset : table.slider_offsets) {
    SliderResponseRow row;
    row.offset = offset;
    SessionDriver driver(config, cruise, "slider table");
    const auto clampTravel = [&](double x) {
      return std::clamp(x, calibration.slider_min, calibration.slider_max);
    };
    driver.commandSlider(calibration.park_position);
    Vec3 ignored = Vec3::Zero();
    double shaft = 0.0;
    advance(
        driver, options.settle_time, [&](double) { return cruise; }, ignored, shaft);
    driver.commandSlider(clampTravel(calibration.park_position + offset));
    row.pitch_rate = elevationRateOver(driver, options.pitch_window, cruise);
    const double sign = row.pitch_rate >= 0.0 ? 1.0 : -1.0;
    HeldAttitudeWindow hold(table.hold_window);
    const double flip = timeUntil(
        driver, cruise, table.flip_timeout,
        [&](double e) { return sign * e >= table.flip_elevation; }, &hold);
    hold.fit(row.end_elevation, row.end_elevation_rate, row.azimuth_rate);
    row.hold_turn = hold.azimuthChange();  // from the end of the pitch window
    row.flip_time = flip < 0.0 ? -1.0 : options.pitch_window + flip;
    driver.commandSlider(clampTravel(calibration.park_position - offset));
    HeldAttitudeWindow back(table.flip_timeout);
    row.return_time = timeUntil(
        driver, cruise, table.flip_timeout, [&](double e) { return sign * e <= 0.0; }, &back);
    row.return_turn = back.azimuthChange();
    rows.push_back(row);
    if (progress)
      progress("slider table: offset " + std::to_string(offset * 1e3) + " mm: pitch rate " +
               std::to_string(row.pitch_rate * kDeg) + " deg/s, flip " +
               std::to_string(row.flip_time) + " s, return " + std::to_string(row.return_time) +
               " s; end of hold: elevation " + std::to_string(row.end_elevation * kDeg) +
               " deg at " + std::to_string(row.end_elevation_rate * kDeg) + " deg/s, azimuth " +
               std::to_string(row.azimuth_rate * kDeg) + " deg/s; azimuth turned " +
               std::to_string(row.hold_turn * kDeg) + " deg holding, " +
               std::to_string(row.return_turn * kDeg) + " deg returning");
  }
  return rows;
}

void writeBuckleTurnTable(const std::vector<BuckleTurnRow>& rows, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "pulse_factor,pulse_duration_s,schedule,turn_by_phase_deg,bias_up_deg,bias_left_deg,"
         "residual_deg\n";
  for (const BuckleTurnRow& r : rows)
    for (const BuckleSchedule* s : {&r.relax, &r.three_level})
      out << r.pulse_factor << ',' << r.pulse_duration << ',' << scheduleName(s->kind) << ','
          << s->deflection * kDeg << ',' << s->bias_up * kDeg << ',' << s->bias_left * kDeg << ','
          << s->phase_spread * kDeg << '\n';
}

void writeSliderTable(const std::vector<SliderResponseRow>& rows, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "offset_mm,pitch_rate_deg_s,flip_time_s,return_time_s,end_elevation_deg,"
         "end_elevation_rate_deg_s,azimuth_rate_deg_s,hold_turn_deg,return_turn_deg\n";
  for (const SliderResponseRow& r : rows)
    out << r.offset * 1e3 << ',' << r.pitch_rate * kDeg << ',' << r.flip_time << ','
        << r.return_time << ',' << r.end_elevation * kDeg << ',' << r.end_elevation_rate * kDeg
        << ',' << r.azimuth_rate * kDeg << ',' << r.hold_turn * kDeg << ',' << r.return_turn * kDeg
        << '\n';
}

}  // namespace flagella::control
