// Validation and YAML storage of the binary-input calibration (docs/model.md 7.3).
#include "flagella_control/calibration.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_control/validation.h"
#include "flagella_control/yaml_text.h"
#include "flagella_sim/core/parameter_set.h"

namespace flagella::control {

namespace {

const char* const kContext = "calibration";

void requireAngle(const std::string& field, double value) {
  requireFinite(kContext, field, value);
  if (!(value > -M_PI && value <= M_PI))
    throw std::invalid_argument("calibration: " + field + " must be in (-pi, pi] rad, got " +
                                numberString(value));
}

void validateSign(const SignResponse& r, const std::string& name) {
  requireFinite(kContext, name + ".yaw_rate", r.yaw_rate);
  if (r.yaw_rate == 0.0)
    throw std::invalid_argument("calibration: " + name + ".yaw_rate must not be 0 rad/s");
  requirePositive(kContext, name + ".circle_radius", r.circle_radius, "m");
  requireAngle(name + ".axis_path_angle", r.axis_path_angle);
  requirePositive(kContext, name + ".speed", r.speed, "m/s");
  requireFinite(kContext, name + ".body_velocity[0]", r.body_velocity[0]);
  requireFinite(kContext, name + ".body_velocity[1]", r.body_velocity[1]);
}

const auto line = commentedLine;

void writeSign(std::ostream& out, const std::string& name, const SignResponse& r,
               const std::string& description) {
  out << line(2, name + ":", description);
  out << line(4, "yaw_rate: " + numberText(r.yaw_rate),
              "d psi/dt, counter-clockwise positive [rad/s]");
  out << line(4, "circle_radius: " + numberText(r.circle_radius),
              "least-squares circle of the head path [m]");
  out << line(4, "axis_path_angle: " + numberText(r.axis_path_angle),
              "path tangent minus heading [rad]");
  out << line(4, "speed: " + numberText(r.speed), "mean head path speed [m/s]");
  out << line(4,
              "body_velocity: [" + numberText(r.body_velocity[0]) + ", " +
                  numberText(r.body_velocity[1]) + "]",
              "[along the head axis, to its left] [m/s]");
}

SignResponse readSign(MapReader& parent, const std::string& key) {
  MapReader m = parent.child(key);
  SignResponse r;
  r.yaw_rate = m.number("yaw_rate");
  r.circle_radius = m.number("circle_radius");
  r.axis_path_angle = m.number("axis_path_angle");
  r.speed = m.number("speed");
  const YAML::Node v = m.get("body_velocity");
  if (!v.IsSequence() || v.size() != 2)
    m.fail(m.field("body_velocity"), "must be a list of 2 numbers [along, left]");
  r.body_velocity[0] = m.parseNumber(v[0], m.field("body_velocity[0]"));
  r.body_velocity[1] = m.parseNumber(v[1], m.field("body_velocity[1]"));
  m.rejectUnknown();
  return r;
}

}  // namespace

void BinaryCalibration::validate() const {
  requirePositive(kContext, "omega", omega, "rad/s");
  requirePositive(kContext, "switch_period", switch_period, "s");
  validateSign(plus, "plus");
  validateSign(minus, "minus");
  if ((plus.yaw_rate > 0.0) == (minus.yaw_rate > 0.0))
    throw std::invalid_argument(
        "calibration: plus.yaw_rate and minus.yaw_rate must have opposite signs, got " +
        numberString(plus.yaw_rate) + " and " + numberString(minus.yaw_rate) + " rad/s");
  requirePositive(kContext, "advance_per_period", advance_per_period, "m");
  requireAngle("advance_angle", advance_angle);
  requireFinite(kContext, "heading_drift_per_period", heading_drift_per_period);
}

BinaryCalibration loadCalibration(const std::string& path) {
  const YAML::Node node = loadSingleKeyFile(path, "calibration", "calibration");
  MapReader m(node, "calibration", path, "calibration");
  BinaryCalibration c;
  c.omega = m.number("omega");
  c.switch_period = m.number("switch_period");
  c.plus = readSign(m, "plus");
  c.minus = readSign(m, "minus");
  c.advance_per_period = m.number("advance_per_period");
  c.advance_angle = m.number("advance_angle");
  c.heading_drift_per_period = m.number("heading_drift_per_period");
  c.source = m.string("source");
  m.rejectUnknown();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw InputFileError(path + ": " + e.what());
  }
  return c;
}

void saveCalibration(const BinaryCalibration& c, const std::string& path) {
  std::ostringstream out;
  out << "# Binary-input calibration of a flagellated robot (docs/model.md 7.3).\n"
         "# Output frame, z up: heading psi = azimuth of the head axis; angles counter-clockwise\n"
         "# positive. SI units: rad/s, s, m, m/s, rad.\n"
         "# plus/minus: steady motion at constant +omega/-omega. Periodic switching: +omega for\n"
         "# switch_period/2, then -omega for switch_period/2; advance_* and heading_drift_* are\n"
         "# per period, the displacement expressed in the frame of the heading at the period "
         "start.\n";
  out << "calibration:\n";
  out << line(2, "omega: " + numberText(c.omega), "|motor rate| of the binary input [rad/s]");
  out << line(2, "switch_period: " + numberText(c.switch_period),
              "T of the switching run [s]: +omega T/2, then -omega T/2");
  writeSign(out, "plus", c.plus, "constant +omega");
  writeSign(out, "minus", c.minus, "constant -omega");
  out << line(2, "advance_per_period: " + numberText(c.advance_per_period),
              "net head displacement per period [m]");
  out << line(2, "advance_angle: " + numberText(c.advance_angle),
              "its direction from the heading at the period start [rad]");
  out << line(2, "heading_drift_per_period: " + numberText(c.heading_drift_per_period),
              "net heading change per period [rad]");
  out << line(2, "source: " + quotedText(c.source), "how it was obtained");

  writeTextFile(path, out.str());
}

}  // namespace flagella::control
