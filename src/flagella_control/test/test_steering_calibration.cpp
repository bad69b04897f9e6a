// The steering calibration (steering_calibration.h): the cycle model fitted to pulses made from a
// known model recovers it (signs, bias, size, phase), the YAML file round-trips exactly, and bad
// fields are named.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "flagella_control/heading.h"
#include "flagella_control/steering_calibration_runner.h"
#include "support/temp_dir.h"

namespace fc = flagella::control;

namespace {

constexpr double kDeg = M_PI / 180.0;

fc::BuckleSchedule knownSchedule() {
  fc::BuckleSchedule s;
  s.pulse_omega = 3.0;
  s.pulse_duration = 2.0;
  s.relax_duration = 12.0;
  s.bias_up = 1.6 * kDeg;
  s.bias_left = -3.2 * kDeg;
  s.deflection = 3.0 * kDeg;
  s.roll_sign = 1.0;
  s.shaft_sign = -1.0;
  s.phase_offset = 1.1;
  return s;
}

TEST(SteeringCalibration, PhaseLawFitRecoversTheModel) {
  const fc::BuckleSchedule truth = knownSchedule();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::normal_distribution<double> noise(0.0, 0.1 * kDeg);
  std::vector<fc::PulseObservation> pulses;
  for (int i = 0; i < 10; ++i) {
    fc::PulseObservation p;
    p.roll = angle(rng);
    p.shaft = 40.0 * angle(rng);  // many turns of the shaft
    truth.predictedTurn(p.roll, p.shaft, p.up, p.left);
    p.up += noise(rng);
    p.left += noise(rng);
    pulses.push_back(p);
  }
  fc::BuckleSchedule fitted;
  fc::fitPhaseLaw(pulses, fitted);
  EXPECT_EQ(fitted.roll_sign, truth.roll_sign);
  EXPECT_EQ(fitted.shaft_sign, truth.shaft_sign);
  EXPECT_NEAR(fitted.bias_up, truth.bias_up, 0.15 * kDeg);
  EXPECT_NEAR(fitted.bias_left, truth.bias_left, 0.15 * kDeg);
  EXPECT_NEAR(fitted.deflection, truth.deflection, 0.15 * kDeg);
  EXPECT_NEAR(fc::wrapAngle(fitted.phase_offset - truth.phase_offset), 0.0, 4 * kDeg);
  EXPECT_LT(fitted.phase_spread, 0.3 * kDeg);
  EXPECT_THROW(fc::fitPhaseLaw({pulses[0], pulses[1]}, fitted), std::invalid_argument);
}

TEST(SteeringCalibration, SliderTurnFitRecoversTheSlopes) {
  // Cycles at +-step off park turn by the phase law plus (up, left) per metre times the offset:
  // the fit returns those slopes whatever the phases.
  fc::BuckleSchedule schedule = knownSchedule();
  constexpr double kStep = 2e-5, kUp = 4.1e3, kLeft = -3.4e3;  // [m], [rad/m]
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const auto side = [&](double offset) {
    std::vector<fc::PulseObservation> pulses(3);
    for (fc::PulseObservation& p : pulses) {
      p.roll = angle(rng);
      p.shaft = 40.0 * angle(rng);
      schedule.predictedTurn(p.roll, p.shaft, p.up, p.left);
      p.up += kUp * offset;
      p.left += kLeft * offset;
    }
    return pulses;
  };
  const auto plus = side(kStep), minus = side(-kStep);
  fc::fitSliderTurn(plus, minus, kStep, schedule);
  EXPECT_NEAR(schedule.up_per_slider, kUp, 1e-9 * kUp);
  EXPECT_NEAR(schedule.left_per_slider, kLeft, 1e-9 * std::abs(kLeft));
  EXPECT_THROW(fc::fitSliderTurn({}, minus, kStep, schedule), std::invalid_argument);
  EXPECT_THROW(fc::fitSliderTurn(plus, minus, 0.0, schedule), std::invalid_argument);
}

TEST(SteeringCalibration, YamlRoundTripsAndNamesBadFields) {
  fc::SteeringCalibration c;
  c.buckling_threshold = 1.505;
  c.cruise_omega = 1.0535;
  c.cruise_speed = 3.6e-4;
  c.relax = knownSchedule();
  c.three_level = knownSchedule();
  c.three_level.kind = fc::BuckleScheduleKind::ThreeLevel;
  c.three_level.relax_duration = 0.0;
  c.three_level.lead_duration = 2.0;
  c.pitch_rate_per_slider = 119.8;
  c.crab_per_slider = -2.27e4;
  c.park_position = -1e-3;
  c.slider_min = -8e-3;
  c.slider_max = 8e-3;
  c.source = "test \"quoted\"";
  c.park_pitch_rate = -7.4e-5;
  c.three_level.up_per_slider = 8.9e3;
  c.three_level.left_per_slider = -472.0;
  flagella::testing::TempDir dir;
  const std::string path = (dir.path() / "steering.yaml").string();
  fc::saveSteeringCalibration(c, path);
  const fc::SteeringCalibration r = fc::loadSteeringCalibration(path);
  EXPECT_EQ(r.cruise_omega, c.cruise_omega);
  EXPECT_EQ(r.relax.bias_left, c.relax.bias_left);
  EXPECT_EQ(r.three_level.lead_duration, c.three_level.lead_duration);
  EXPECT_EQ(r.three_level.kind, fc::BuckleScheduleKind::ThreeLevel);
  EXPECT_EQ(r.pitch_rate_per_slider, c.pitch_rate_per_slider);
  EXPECT_EQ(r.crab_per_slider, c.crab_per_slider);
  EXPECT_EQ(r.source, c.source);
  EXPECT_EQ(r.park_pitch_rate, c.park_pitch_rate);
  EXPECT_EQ(r.three_level.up_per_slider, c.three_level.up_per_slider);
  EXPECT_EQ(r.three_level.left_per_slider, c.three_level.left_per_slider);
  // Files written before these fields load with them 0.
  {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const char* key : {"park_pitch_rate:", "up_per_slider:", "left_per_slider:"})
      for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key)) {
        const std::size_t line = text.rfind('\n', at) + 1;  // the whole line, indent and all
        text.erase(line, text.find('\n', at) - line + 1);
      }
    const std::string old_path = (dir.path() / "old.yaml").string();
    std::ofstream(old_path) << text;
    const fc::SteeringCalibration old = fc::loadSteeringCalibration(old_path);
    EXPECT_EQ(old.park_pitch_rate, 0.0);
    EXPECT_EQ(old.three_level.up_per_slider, 0.0);
    EXPECT_EQ(old.relax.left_per_slider, 0.0);
  }
  // A crab law of 0 cannot be inverted by the offset steering.
  fc::SteeringCalibration no_crab = c;
  no_crab.crab_per_slider = 0.0;
  try {
    no_crab.validate();
    ADD_FAILURE() << "accepted crab_per_slider = 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("crab_per_slider"), std::string::npos) << e.what();
  }
  // cruise above the threshold
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "cruise_omega: 1.0535";
  text.replace(text.find(key), key.size(), "cruise_omega: 2.5");
  std::ofstream(path) << text;
  try {
    fc::loadSteeringCalibration(path);
    ADD_FAILURE() << "accepted cruise_omega above the threshold";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cruise_omega"), std::string::npos) << e.what();
  }
}

}  // namespace
