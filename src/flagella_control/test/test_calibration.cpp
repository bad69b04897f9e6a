// The binary-input calibration (docs/model.md 7.3): YAML storage and validation, and the simulator
// measurement checked against independent truths: kinematic identities of steady circling,
// mirror symmetry between the motor signs, consistency of the switching run with the
// constant-sign runs, and the lateral head force as the cause of the yaw (docs/model.md 3.3).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include "flagella_control/calibration.h"
#include "flagella_control/calibration_runner.h"
#include "flagella_control/heading.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"

namespace units = flagella::units;

namespace flagella::control {
namespace {

const std::string kConfig = std::string(FLAGELLA_CONFIG_DIR) + "/interface_path_planning.yaml";

std::string tempFile(const std::string& name) { return ::testing::TempDir() + name; }

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

using flagella::testing::errorMessageOf;

// Values with long binary expansions, so that an exact round trip is a real test.
BinaryCalibration example() {
  BinaryCalibration c;
  c.omega = units::rpmToRadPerSec(43.27);
  c.switch_period = 10.0;
  c.plus.yaw_rate = -0.1 / 3.0;
  c.plus.circle_radius = 0.1 / 3.0;
  c.plus.axis_path_angle = 2.0 * M_PI / 3.0;
  c.plus.speed = std::sqrt(2.0) * 1e-3;
  c.plus.body_velocity[0] = -1.0 / 7.0 * 1e-2;
  c.plus.body_velocity[1] = std::exp(-6.0);
  c.minus = c.plus;
  c.minus.yaw_rate = 1.0 / 31.0;
  c.minus.axis_path_angle = M_PI;  // the closed end of (-pi, pi]
  c.minus.body_velocity[1] = -std::exp(-6.0) * (1.0 + 1e-15);
  c.advance_per_period = M_PI * 4e-3;
  c.advance_angle = 3.0 - 1e-9;
  c.heading_drift_per_period = -std::exp(-13.0);
  c.source = "config/x.yaml; \"quoted\" \\ tab\t # not a comment: colon";
  return c;
}

// A valid file with one line replaced (the line holding `from`).
std::string exampleWith(const std::string& from, const std::string& to) {
  const std::string path = tempFile("calibration_base.yaml");
  saveCalibration(example(), path);
  std::string text = readText(path);
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const std::string edited = tempFile("calibration_edited.yaml");
  writeText(edited, text);
  return edited;
}

// ---- (a) storage and validation --------------------------------------------------------------

TEST(CalibrationYaml, SaveLoadRoundTripIsExact) {
  const BinaryCalibration c = example();
  ASSERT_NO_THROW(c.validate());
  const std::string path = tempFile("calibration_roundtrip.yaml");
  saveCalibration(c, path);
  const BinaryCalibration r = loadCalibration(path);
  EXPECT_EQ(r.omega, c.omega);
  EXPECT_EQ(r.switch_period, c.switch_period);
  for (const auto& [a, b] :
       {std::make_pair(&r.plus, &c.plus), std::make_pair(&r.minus, &c.minus)}) {
    EXPECT_EQ(a->yaw_rate, b->yaw_rate);
    EXPECT_EQ(a->circle_radius, b->circle_radius);
    EXPECT_EQ(a->axis_path_angle, b->axis_path_angle);
    EXPECT_EQ(a->speed, b->speed);
    EXPECT_EQ(a->body_velocity[0], b->body_velocity[0]);
    EXPECT_EQ(a->body_velocity[1], b->body_velocity[1]);
  }
  EXPECT_EQ(r.advance_per_period, c.advance_per_period);
  EXPECT_EQ(r.advance_angle, c.advance_angle);
  EXPECT_EQ(r.heading_drift_per_period, c.heading_drift_per_period);
  EXPECT_EQ(r.source, c.source);

  // Readable: a comment header, the documented keys, units in comments.
  const std::string text = readText(path);
  EXPECT_EQ(text.rfind("# ", 0), 0u);
  for (const char* key : {"calibration:", "  plus:", "  minus:", "    body_velocity: [",
                          "advance_per_period:", "heading_drift_per_period:", "[rad/s]", "[m/s]"})
    EXPECT_NE(text.find(key), std::string::npos) << key;
}

TEST(CalibrationYaml, LoadErrorsNameTheFileAndTheField) {
  const auto loadError = [](const std::string& path) {
    return errorMessageOf<std::runtime_error>([&] { loadCalibration(path); });
  };
  std::string path = exampleWith("  advance_angle:", "  not_advance_angle:");
  std::string message = loadError(path);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("calibration.advance_angle"), std::string::npos) << message;  // missing

  path = exampleWith("    speed: ", "    speed: fast #");
  message = loadError(path);
  EXPECT_NE(message.find("calibration.plus.speed"), std::string::npos) << message;

  path = exampleWith("  source:", "  colour: blue\n  source:");
  message = loadError(path);
  EXPECT_NE(message.find("calibration.colour"), std::string::npos) << message;  // unknown key

  path = exampleWith("calibration:", "extra: 1\ncalibration:");
  EXPECT_NE(loadError(path).find("extra"), std::string::npos) << loadError(path);

  path = exampleWith("    body_velocity: [", "    body_velocity: [1, ");  // three entries
  EXPECT_NE(loadError(path).find("calibration.plus.body_velocity"), std::string::npos)
      << loadError(path);

  path = exampleWith("  switch_period: 10", "  switch_period: -10");  // parses, fails validation
  message = loadError(path);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("switch_period"), std::string::npos) << message;

  message = loadError(tempFile("no_such_calibration.yaml"));
  EXPECT_NE(message.find("no_such_calibration.yaml"), std::string::npos) << message;
}

TEST(CalibrationYaml, ValidateRejectsUnusableValuesNamingTheField) {
  const auto check = [](const std::string& field,
                        const std::function<void(BinaryCalibration&)>& f) {
    BinaryCalibration c = example();
    f(c);
    const std::string message = errorMessageOf<std::invalid_argument>([&] { c.validate(); });
    EXPECT_NE(message.find(field), std::string::npos) << field << ": " << message;
  };
  check("omega", [](BinaryCalibration& c) { c.omega = 0.0; });
  check("switch_period", [](BinaryCalibration& c) { c.switch_period = -1.0; });
  check("plus.yaw_rate", [](BinaryCalibration& c) { c.plus.yaw_rate = NAN; });
  check("minus.yaw_rate", [](BinaryCalibration& c) { c.minus.yaw_rate = 0.0; });
  check("opposite signs", [](BinaryCalibration& c) { c.minus.yaw_rate = c.plus.yaw_rate; });
  check("minus.circle_radius", [](BinaryCalibration& c) { c.minus.circle_radius = 0.0; });
  check("plus.axis_path_angle", [](BinaryCalibration& c) { c.plus.axis_path_angle = -M_PI; });
  check("plus.speed", [](BinaryCalibration& c) { c.plus.speed = INFINITY; });
  check("minus.body_velocity[1]", [](BinaryCalibration& c) { c.minus.body_velocity[1] = NAN; });
  check("advance_per_period", [](BinaryCalibration& c) { c.advance_per_period = 0.0; });
  check("advance_angle", [](BinaryCalibration& c) { c.advance_angle = 4.0; });
  check("heading_drift_per_period", [](BinaryCalibration& c) { c.heading_drift_per_period = NAN; });
}

TEST(CalibrationOptions, ValidateRejectsBadOptions) {
  const auto message = [](const std::function<void(CalibrationOptions&)>& f) {
    CalibrationOptions o;
    f(o);
    return errorMessageOf<std::invalid_argument>([&] { o.validate(); });
  };
  EXPECT_NO_THROW(CalibrationOptions().validate());
  EXPECT_NE(message([](auto& o) { o.switch_period = 0.0; }).find("switch_period"),
            std::string::npos);
  EXPECT_NE(message([](auto& o) { o.omega = -1.0; }).find("omega"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.measure_time = NAN; }).find("measure_time"), std::string::npos);
  EXPECT_NE(message([](auto& o) { o.measure_periods = 0; }).find("measure_periods"),
            std::string::npos);
  // T/2 must be a whole number of time steps (dt = 0.01 s): reported when the run starts.
  CalibrationOptions odd;
  odd.switch_period = 10.005;
  const flagella::SimulationConfig config = flagella::loadSimulationConfig(kConfig);
  const std::string m =
      errorMessageOf<std::invalid_argument>([&] { measureSwitching(config, 1.0, odd); });
  EXPECT_NE(m.find("switch_period/2"), std::string::npos) << m;
}

// ---- (b), (c) the simulator measurement ------------------------------------------------------

// Short runs: 20 s settling (the transient after the soft start decays within a few of the
// config's 2.2 s intrinsic time scale) and 40 s of circling (about 1.3 rad of arc); switching
// with T = 10 s, 1 + 4 periods. About 170 s simulated in total (~6 s wall).
CalibrationOptions shortOptions() {
  CalibrationOptions o;
  o.settle_time = 20.0;
  o.measure_time = 40.0;
  o.switch_period = 10.0;
  o.settle_periods = 1;
  o.measure_periods = 4;
  return o;
}

class InterfaceCalibration : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    config_ = new flagella::SimulationConfig(flagella::loadSimulationConfig(kConfig));
    calibration_ = new BinaryCalibration(calibrate(*config_, shortOptions()));
  }
  static void TearDownTestSuite() {
    delete calibration_;
    delete config_;
  }
  static flagella::SimulationConfig* config_;
  static BinaryCalibration* calibration_;
};
flagella::SimulationConfig* InterfaceCalibration::config_ = nullptr;
BinaryCalibration* InterfaceCalibration::calibration_ = nullptr;

TEST_F(InterfaceCalibration, ResultIsValidAndDescribesItsSource) {
  const BinaryCalibration& c = *calibration_;
  EXPECT_NO_THROW(c.validate());
  EXPECT_DOUBLE_EQ(c.omega, units::rpmToRadPerSec(43.27));  // from the config's motor.omega_rpm
  EXPECT_EQ(c.switch_period, 10.0);
  EXPECT_NE(c.source.find("interface_path_planning.yaml"), std::string::npos) << c.source;
  EXPECT_NE(c.source.find("measure 40 s"), std::string::npos) << c.source;
}

// Steady circling at constant sign: the path speed is |yaw rate| times the circle radius, the
// mean velocity in the heading frame has the path speed as its length, and its direction is the
// angle between the head axis and the path tangent. The head wobbles at the spin frequency, which
// makes the mean |v| slightly exceed |mean v|: 2 % allows for that (found: < 0.1 %).
TEST_F(InterfaceCalibration, ConstantSignObeysCirclingKinematics) {
  for (const SignResponse* r : {&calibration_->plus, &calibration_->minus}) {
    SCOPED_TRACE(r == &calibration_->plus ? "plus" : "minus");
    EXPECT_NEAR(r->speed, std::abs(r->yaw_rate) * r->circle_radius, 0.02 * r->speed);
    EXPECT_NEAR(std::hypot(r->body_velocity[0], r->body_velocity[1]), r->speed, 0.02 * r->speed);
    EXPECT_NEAR(
        wrapAngle(r->axis_path_angle - std::atan2(r->body_velocity[1], r->body_velocity[0])), 0.0,
        0.02);
    // The config gives a circle of about one tail length (Ch.4): order-of-magnitude sanity.
    EXPECT_GT(r->circle_radius, 0.2 * config_->robot->filamentLength());
    EXPECT_LT(r->circle_radius, 5.0 * config_->robot->filamentLength());
  }
}

// Straight tails with spokes in the horizontal plane, a head restraint that is even in height and
// pitch, and a lateral head force odd in the spin (docs/model.md 3.3): the model is exactly
// symmetric under the mirror through the vertical plane containing the head axis, which reverses
// the spin. The two runs are then mirror images up to solver round-off (found: ~1e-14 relative);
// 1e-6 leaves room for Newton-termination differences while still catching any real asymmetry.
TEST_F(InterfaceCalibration, MotorSignsAreMirrorImages) {
  const SignResponse& p = calibration_->plus;
  const SignResponse& m = calibration_->minus;
  const double tol = 1e-6;
  EXPECT_NEAR(p.yaw_rate, -m.yaw_rate, tol * std::abs(p.yaw_rate));
  EXPECT_NEAR(p.circle_radius, m.circle_radius, tol * p.circle_radius);
  EXPECT_NEAR(p.speed, m.speed, tol * p.speed);
  EXPECT_NEAR(p.axis_path_angle, -m.axis_path_angle, tol);
  EXPECT_NEAR(p.body_velocity[0], m.body_velocity[0], tol * p.speed);
  EXPECT_NEAR(p.body_velocity[1], -m.body_velocity[1], tol * p.speed);
}

// Equal halves: the heading turns by plus.yaw_rate T/2 and back by minus.yaw_rate T/2, so the net
// drift is small compared with one half's turn (found: ~1e-5 of it).
TEST_F(InterfaceCalibration, EqualHalvesDoNotDrift) {
  const BinaryCalibration& c = *calibration_;
  const double half_turn = std::abs(c.plus.yaw_rate) * 0.5 * c.switch_period;
  EXPECT_LT(std::abs(c.heading_drift_per_period), 0.05 * half_turn);
}

// Displacement while holding one sign for time tau from heading 0, with a = w tau:
// integral of R(w t) v_body dt = (1/w) [[sin a, -(1 - cos a)], [1 - cos a, sin a]] v_body.
Eigen::Vector2d holdDisplacement(const SignResponse& r, double tau) {
  const double w = r.yaw_rate, a = w * tau;
  const Eigen::Vector2d v(r.body_velocity[0], r.body_velocity[1]);
  Eigen::Matrix2d m;
  m << std::sin(a), -(1.0 - std::cos(a)), 1.0 - std::cos(a), std::sin(a);
  return m * v / w;
}

// The switching run against the constant-sign runs: + half, then the - half rotated by the
// heading the + half reached. Each switch costs a transient (the motor jumps, the tails re-coil
// over ~ the 2.2 s intrinsic time), during which the robot moves less than the steady response
// says: the prediction is an upper bound. Found: measured/predicted ~0.94 in magnitude and ~0.1 deg
// in direction at T = 10 s. Tolerances: 15 % and 3 deg.
TEST_F(InterfaceCalibration, SwitchingAdvanceMatchesTheConstantSignResponses) {
  const BinaryCalibration& c = *calibration_;
  const double half = 0.5 * c.switch_period;
  const double a_plus = c.plus.yaw_rate * half;
  const Eigen::Vector2d predicted =
      holdDisplacement(c.plus, half) +
      Eigen::Rotation2Dd(a_plus).toRotationMatrix() * holdDisplacement(c.minus, half);
  const double ratio = c.advance_per_period / predicted.norm();
  const double angle_error = wrapAngle(c.advance_angle - std::atan2(predicted.y(), predicted.x()));
  std::printf(
      "switching T = %g s: advance %.3f mm/period at %.2f deg; predicted from constant "
      "sign %.3f mm at %.2f deg (ratio %.3f)\n",
      c.switch_period, units::metresToMm(c.advance_per_period), units::radToDeg(c.advance_angle),
      units::metresToMm(predicted.norm()),
      units::radToDeg(std::atan2(predicted.y(), predicted.x())), ratio);
  EXPECT_GT(ratio, 0.85);
  EXPECT_LT(ratio, 1.05);
  EXPECT_LT(std::abs(angle_error), units::degToRad(3.0));
}

// The yaw comes from the lateral head force F = -C_yr mu0 R L_head Omega_h xhat
// (docs/model.md 3.3): with C_yr = 0 the model is also symmetric under a half turn about the head
// axis (up <-> down), which reverses any yaw, so there is none. Stokes flow is linear in the forces
// and the path bends slowly, so the yaw rate should scale about linearly with C_yr: cutting C_yr by
// 30 % must cut the yaw rate by about 30 % (found: ratio 0.700), in the same sense. Tolerance 0.05
// on the ratio.
TEST_F(InterfaceCalibration, WeakerLateralHeadForceTurnsLess) {
  double c_yr = 0.0;
  for (const flagella::EffectSpec& e : config_->effects)
    if (e.name == "interface_lateral_force")
      for (const auto& [name, value] : e.parameters)
        if (name == "C_yr") c_yr = value;
  ASSERT_GT(c_yr, 0.0) << "the config sets effects.interface_lateral_force.C_yr";
  char assignment[64];
  std::snprintf(assignment, sizeof assignment, "effects.interface_lateral_force.C_yr=%.17g",
                0.7 * c_yr);
  const flagella::SimulationConfig weaker = flagella::loadSimulationConfig(kConfig, {assignment});
  const SignResponse r =
      measureSignResponse(weaker, calibrationOmega(weaker, shortOptions()), shortOptions());
  const double ratio = r.yaw_rate / calibration_->plus.yaw_rate;
  std::printf("C_yr %.3g -> %.3g: yaw rate %.5f -> %.5f rad/s (ratio %.3f)\n", c_yr, 0.7 * c_yr,
              calibration_->plus.yaw_rate, r.yaw_rate, ratio);
  EXPECT_NEAR(ratio, 0.7, 0.05);
}

}  // namespace
}  // namespace flagella::control
