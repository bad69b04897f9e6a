// Validation, pulse-model evaluation and YAML storage of the steering calibration
// (docs/model.md 7.4).
#include "flagella_control/steering_calibration.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "flagella_control/heading.h"
#include "flagella_control/validation.h"
#include "flagella_control/yaml_text.h"
#include "flagella_sim/core/parameter_set.h"

namespace flagella::control {

namespace {

const char* const kContext = "steering calibration";

void requireSign(const std::string& field, double value) {
  if (value != 1.0 && value != -1.0)
    throw std::invalid_argument(std::string(kContext) + ": " + field + " must be 1 or -1, got " +
                                numberString(value));
}

void validateSchedule(const BuckleSchedule& s, const std::string& name, double threshold) {
  requireInRange(kContext, name + ".lead_omega", s.lead_omega, 0.0, threshold);
  requireInRange(kContext, name + ".lead_duration", s.lead_duration, 0.0, 600.0);
  requireInRange(kContext, name + ".pulse_omega", s.pulse_omega, threshold, 100.0 * threshold);
  requirePositive(kContext, name + ".pulse_duration", s.pulse_duration, "s");
  requireInRange(kContext, name + ".relax_omega", s.relax_omega, 0.0, threshold);
  requireInRange(kContext, name + ".relax_duration", s.relax_duration, 0.0, 600.0);
  requireInRange(kContext, name + ".bias_up", s.bias_up, -M_PI / 2, M_PI / 2);
  requireInRange(kContext, name + ".bias_left", s.bias_left, -M_PI / 2, M_PI / 2);
  requireInRange(kContext, name + ".deflection", s.deflection, 1e-4, M_PI / 2);
  requireSign(name + ".roll_sign", s.roll_sign);
  requireSign(name + ".shaft_sign", s.shaft_sign);
  requireInRange(kContext, name + ".phase_offset", s.phase_offset, -M_PI, M_PI);
  requireFinite(kContext, name + ".up_per_slider", s.up_per_slider);
  requireFinite(kContext, name + ".left_per_slider", s.left_per_slider);
  requireInRange(kContext, name + ".phase_spread", s.phase_spread, 0.0, M_PI);
}

const auto line = commentedLine;

void writeSchedule(std::ostream& out, const std::string& name, const BuckleSchedule& s,
                   const std::string& description) {
  out << line(2, name + ":", description);
  out << line(4, "lead_omega: " + numberText(s.lead_omega), "omega_1 before the pulse [rad/s]");
  out << line(4, "lead_duration: " + numberText(s.lead_duration), "[s]");
  out << line(4, "pulse_omega: " + numberText(s.pulse_omega), "omega_2 > omega_b [rad/s]");
  out << line(4, "pulse_duration: " + numberText(s.pulse_duration), "[s]");
  out << line(4, "relax_omega: " + numberText(s.relax_omega), "omega_1 after the pulse [rad/s]");
  out << line(4, "relax_duration: " + numberText(s.relax_duration), "[s]");
  out << line(4, "bias_up: " + numberText(s.bias_up), "constant turn per cycle, up [rad]");
  out << line(4, "bias_left: " + numberText(s.bias_left), "constant turn per cycle, left [rad]");
  out << line(4, "deflection: " + numberText(s.deflection),
              "size of the phase-dependent turn per cycle [rad]");
  out << line(4, "roll_sign: " + numberText(s.roll_sign), "chi = roll_sign roll");
  out << line(4, "shaft_sign: " + numberText(s.shaft_sign), "  + shaft_sign shaft");
  out << line(4, "phase_offset: " + numberText(s.phase_offset), "  + phase_offset [rad]");
  out << line(4, "phase_spread: " + numberText(s.phase_spread),
              "RMS residual of the turn over the calibration pulses [rad]");
  out << line(4, "up_per_slider: " + numberText(s.up_per_slider),
              "turn up per metre of slider off park held through the cycle [rad/m]");
  out << line(4, "left_per_slider: " + numberText(s.left_per_slider),
              "turn left per metre of slider off park held through the cycle [rad/m]");
}

BuckleSchedule readSchedule(MapReader& parent, const std::string& key, BuckleScheduleKind kind) {
  MapReader m = parent.child(key);
  BuckleSchedule s;
  s.kind = kind;
  s.lead_omega = m.number("lead_omega");
  s.lead_duration = m.number("lead_duration");
  s.pulse_omega = m.number("pulse_omega");
  s.pulse_duration = m.number("pulse_duration");
  s.relax_omega = m.number("relax_omega");
  s.relax_duration = m.number("relax_duration");
  s.bias_up = m.number("bias_up");
  s.bias_left = m.number("bias_left");
  s.deflection = m.number("deflection");
  s.roll_sign = m.number("roll_sign");
  s.shaft_sign = m.number("shaft_sign");
  s.phase_offset = m.number("phase_offset");
  s.phase_spread = m.number("phase_spread");
  if (m.has("up_per_slider")) s.up_per_slider = m.number("up_per_slider");
  if (m.has("left_per_slider")) s.left_per_slider = m.number("left_per_slider");
  m.rejectUnknown();
  return s;
}

}  // namespace

const char* scheduleName(BuckleScheduleKind kind) {
  return kind == BuckleScheduleKind::Relax ? "relax" : "three_level";
}

BuckleScheduleKind scheduleFromName(const std::string& name) {
  if (name == "relax") return BuckleScheduleKind::Relax;
  if (name == "three_level") return BuckleScheduleKind::ThreeLevel;
  throw std::invalid_argument("buckle schedule must be 'relax' or 'three_level', got '" + name +
                              "'");
}

double BuckleSchedule::omegaAt(double s, double cruise_omega) const {
  if (s < lead_duration) return lead_omega;
  s -= lead_duration;
  if (s < pulse_duration) return pulse_omega;
  s -= pulse_duration;
  if (s < relax_duration) return relax_omega;
  return cruise_omega;
}

double BuckleSchedule::direction(double roll, double shaft) const {
  return wrapAngle(roll_sign * roll + shaft_sign * shaft + phase_offset);
}

void BuckleSchedule::turnToward(double chi, double& up, double& left) const {
  up = bias_up + deflection * std::cos(chi);
  left = bias_left + deflection * std::sin(chi);
}

void SteeringCalibration::validate() const {
  requirePositive(kContext, "buckling_threshold", buckling_threshold, "rad/s");
  requireInRange(kContext, "cruise_omega", cruise_omega, 1e-9, buckling_threshold);
  requirePositive(kContext, "cruise_speed", cruise_speed, "m/s");
  validateSchedule(relax, "relax", buckling_threshold);
  validateSchedule(three_level, "three_level", buckling_threshold);
  requireFinite(kContext, "pitch_rate_per_slider", pitch_rate_per_slider);
  if (pitch_rate_per_slider == 0.0)
    throw std::invalid_argument("steering calibration: pitch_rate_per_slider must not be 0");
  requireFinite(kContext, "crab_per_slider", crab_per_slider);
  if (crab_per_slider == 0.0)
    throw std::invalid_argument("steering calibration: crab_per_slider must not be 0");
  requireFinite(kContext, "slider_min", slider_min);
  requireInRange(kContext, "slider_max", slider_max, slider_min + 1e-9, 1.0);
  requireInRange(kContext, "park_position", park_position, slider_min, slider_max);
  requireFinite(kContext, "park_pitch_rate", park_pitch_rate);
}

SteeringCalibration loadSteeringCalibration(const std::string& path) {
  const YAML::Node node = loadSingleKeyFile(path, "steering_calibration", "steering calibration");
  MapReader m(node, "steering_calibration", path, "steering calibration");
  SteeringCalibration c;
  c.buckling_threshold = m.number("buckling_threshold");
  c.cruise_omega = m.number("cruise_omega");
  c.cruise_speed = m.number("cruise_speed");
  c.relax = readSchedule(m, "relax", BuckleScheduleKind::Relax);
  c.three_level = readSchedule(m, "three_level", BuckleScheduleKind::ThreeLevel);
  c.pitch_rate_per_slider = m.number("pitch_rate_per_slider");
  c.crab_per_slider = m.number("crab_per_slider");
  c.park_position = m.number("park_position");
  if (m.has("park_pitch_rate")) c.park_pitch_rate = m.number("park_pitch_rate");
  c.slider_min = m.number("slider_min");
  c.slider_max = m.number("slider_max");
  c.source = m.string("source");
  m.rejectUnknown();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw InputFileError(path + ": " + e.what());
  }
  return c;
}

void saveSteeringCalibration(const SteeringCalibration& c, const std::string& path) {
  std::ostringstream out;
  out << "# Steering calibration of the helical robot with a mass-transformer (docs/model.md "
         "7.4).\n"
         "# Output frame, z up. A buckle cycle turns the direction of travel by (bias_up, "
         "bias_left)\n"
         "# plus `deflection` toward chi = roll_sign roll + shaft_sign shaft + phase_offset, an\n"
         "# angle of the plane normal to the direction of travel from up toward the left. SI "
         "units.\n";
  out << "steering_calibration:\n";
  out << line(2, "buckling_threshold: " + numberText(c.buckling_threshold), "omega_b [rad/s]");
  out << line(2, "cruise_omega: " + numberText(c.cruise_omega), "omega_3 < omega_b [rad/s]");
  out << line(2, "cruise_speed: " + numberText(c.cruise_speed), "net speed at cruise [m/s]");
  writeSchedule(out, "relax", c.relax, "pulse, then relax the helix, then cruise");
  writeSchedule(out, "three_level", c.three_level, "omega_1, omega_2, then cruise (omega_3)");
  out << line(2, "pitch_rate_per_slider: " + numberText(c.pitch_rate_per_slider),
              "nose-up pitch rate per slider metre, head horizontal [rad/s/m]");
  out << line(2, "crab_per_slider: " + numberText(c.crab_per_slider),
              "course minus axis azimuth per slider metre, cruising level [rad/m]");
  out << line(2, "park_position: " + numberText(c.park_position), "slider at l = 0 [m]");
  out << line(2, "park_pitch_rate: " + numberText(c.park_pitch_rate),
              "nose-up pitch rate cruising at park [rad/s]");
  out << line(2, "slider_min: " + numberText(c.slider_min), "travel [m]");
  out << line(2, "slider_max: " + numberText(c.slider_max), "travel [m]");
  out << line(2, "source: " + quotedText(c.source), "how it was obtained");
  writeTextFile(path, out.str());
}

}  // namespace flagella::control
