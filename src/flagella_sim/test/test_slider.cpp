// The mass-transformer's slider (docs/model.md 5): trapezoidal moves against their closed form,
// rate and acceleration limits, hard stops never passed and reported, the COM offset
// l = l_0 + (m_s/m_h) x_s it gives the com_offset couple every step, the config section and its
// errors, and a failed step leaving the slider where it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/actuation/slider.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/simulation/simulation.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr double kSubStep = 1e-3;  // the slider's internal sub-step [s]

SliderSpec testSpec() {
  SliderSpec s;
  s.lead = 0.5e-3;
  s.max_screw_rate = 2.0 * M_PI * 5.0;  // 5 rev/s: 2.5 mm/s
  s.max_screw_accel = 2.0 * M_PI * 50;  // 25 mm/s^2: full speed in 0.1 s
  s.travel_min = -8e-3;
  s.travel_max = 8e-3;
  return s;
}

// Closed form of a move from rest over D > v^2/a: accelerate, cruise, brake (trapezoid).
double trapezoid(double t, double D, double v, double a) {
  const double T = D / v + v / a;  // arrival
  if (t <= v / a) return 0.5 * a * t * t;
  if (t <= T - v / a) return v * t - 0.5 * v * v / a;
  if (t <= T) return D - 0.5 * a * (T - t) * (T - t);
  return D;
}

TEST(Slider, LongMoveFollowsTheTrapezoid) {
  const SliderSpec spec = testSpec();
  const double v = spec.maxSpeed(), a = spec.maxAcceleration();
  EXPECT_NEAR(v, 2.5e-3, 1e-15);
  EXPECT_NEAR(a, 25e-3, 1e-15);
  Slider slider(spec);
  const double D = 6e-3, dt = 0.01;
  slider.setTarget(D);
  double previous_v = 0.0, t = 0.0, arrival = -1.0;
  for (int k = 0; k < 400; ++k) {
    slider.advance(dt);
    t += dt;
    const SliderState& s = slider.state();
    EXPECT_NEAR(s.position, trapezoid(t, D, v, a), v * kSubStep) << "t = " << t;
    EXPECT_LE(std::abs(s.velocity), v * (1 + 1e-12));
    EXPECT_LE(std::abs(s.velocity - previous_v), a * dt * (1 + 1e-9));
    EXPECT_LE(s.position, D + 1e-12);  // no overshoot
    previous_v = s.velocity;
    if (arrival < 0.0 && s.position == D && s.velocity == 0.0) arrival = t;
  }
  EXPECT_NEAR(arrival, D / v + v / a, 2 * kSubStep + dt);
  EXPECT_FALSE(slider.state().at_stop);
  EXPECT_EQ(slider.state().stop_hits, 0);
}

TEST(Slider, ShortMoveIsATriangle) {
  const SliderSpec spec = testSpec();
  const double a = spec.maxAcceleration();
  Slider slider(spec);
  const double D = -1e-4;  // below v^2/a = 0.25 mm: never reaches full speed
  slider.setTarget(D);
  double peak = 0.0, t = 0.0, arrival = -1.0;
  while (t < 1.0) {
    slider.advance(kSubStep);
    t += kSubStep;
    peak = std::max(peak, std::abs(slider.state().velocity));
    if (arrival < 0.0 && slider.state().position == D) arrival = t;
  }
  EXPECT_NEAR(arrival, 2.0 * std::sqrt(std::abs(D) / a), 3 * kSubStep);
  EXPECT_NEAR(peak, std::sqrt(std::abs(D) * a), a * 2 * kSubStep);
  EXPECT_NEAR(slider.screwRate(), 0.0, 0.0);
}

TEST(Slider, HardStopsAreNeverPassedAndAreReported) {
  Slider slider(testSpec());
  slider.setTarget(0.05);  // far beyond the 8 mm stop
  for (int k = 0; k < 1000; ++k) {
    slider.advance(0.01);
    ASSERT_LE(slider.state().position, 8e-3);
  }
  EXPECT_EQ(slider.state().position, 8e-3);
  EXPECT_TRUE(slider.state().at_stop);
  EXPECT_EQ(slider.state().stop_hits, 1);  // one arrival, however long it pushes
  slider.setTarget(0.0);
  slider.advance(0.5);
  EXPECT_FALSE(slider.state().at_stop);
  EXPECT_LT(slider.state().position, 8e-3);
  slider.setTarget(-1.0);
  for (int k = 0; k < 1000; ++k) slider.advance(0.01);
  EXPECT_EQ(slider.state().position, -8e-3);
  EXPECT_EQ(slider.state().stop_hits, 2);
  EXPECT_THROW(slider.setTarget(std::nan("")), std::invalid_argument);
}

TEST(Slider, OffsetIsNeutralPlusMassRatioTimesPosition) {
  SliderSpec spec = testSpec();
  spec.mass = 0.012;
  spec.initial_position = 3e-3;
  const Slider slider(spec);
  // l = l_0 + (m_s/m_h) x_s (docs/model.md 5)
  EXPECT_NEAR(slider.comOffset(1e-3, 0.048), 1e-3 + 0.25 * 3e-3, 1e-18);
}

TEST(Slider, SpecErrorsNameTheField) {
  auto message = [](SliderSpec s) {
    return testing::errorMessageOf<ConfigError>([&] { Slider{s}; });
  };
  SliderSpec s = testSpec();
  s.mass = -1.0;
  EXPECT_NE(message(s).find("slider.mass"), std::string::npos);
  s = testSpec();
  s.travel_max = -1e-3;
  EXPECT_NE(message(s).find("slider.travel_max"), std::string::npos);
  s = testSpec();
  s.initial_position = 0.02;
  EXPECT_NE(message(s).find("slider.initial_position"), std::string::npos);
}

// ---- in the simulation ------------------------------------------------------------------------

std::vector<std::string> sliderOverrides() {
  return {"motor.omega_rpm=0",        "effects.com_offset.offset=1e-3",
          "slider.mass=0.012",        "slider.lead=5e-4",
          "slider.max_screw_rpm=300", "slider.travel_min=-0.008",
          "slider.travel_max=0.008",  "simulation.dt=0.01"};
}

TEST(Slider, SimulationDrivesTheCoupleOffsetEveryStep) {
  const SimulationConfig config =
      loadSimulationConfig(std::string(kConfigDir) + "/helical_robot.yaml", sliderOverrides());
  ASSERT_TRUE(config.slider.enabled);
  Simulation sim(config);
  ASSERT_NE(sim.slider(), nullptr);
  const double head_mass = sim.parameter("effects.com_offset.head_mass");
  EXPECT_DOUBLE_EQ(sim.parameter("effects.com_offset.offset"), 1e-3);
  sim.slider()->setTarget(5e-3);
  for (int k = 0; k < 40; ++k) {
    sim.step();
    const double x = sim.slider()->state().position;
    EXPECT_DOUBLE_EQ(sim.parameter("effects.com_offset.offset"), 1e-3 + 0.012 / head_mass * x);
  }
  EXPECT_GT(sim.slider()->state().position, 0.5e-3);  // it moved (2.5 mm/s for 0.4 s)
  const std::string message = testing::errorMessageOf<ConfigError>(
      [&] { sim.setParameter("effects.com_offset.offset", 2e-3); });
  EXPECT_NE(message.find("follows the slider"), std::string::npos) << message;
}

TEST(Slider, ConfigNeedsTheCoupleAndRejectsUnknownFields) {
  const std::string path = std::string(kConfigDir) + "/helical_robot.yaml";
  std::vector<std::string> bad = sliderOverrides();
  bad.push_back("slider.stroke=1");
  std::string message =
      testing::errorMessageOf<ConfigError>([&] { loadSimulationConfig(path, bad); });
  EXPECT_NE(message.find("slider.stroke"), std::string::npos) << message;
  bad = sliderOverrides();
  bad.push_back("slider.max_screw_rpm=0");
  message = testing::errorMessageOf<ConfigError>([&] { loadSimulationConfig(path, bad); });
  EXPECT_NE(message.find("slider.max_screw_rpm"), std::string::npos) << message;
  message = testing::errorMessageOf<ConfigError>([&] {
    loadSimulationConfig(std::string(kConfigDir) + "/granular_design1.yaml", {"slider.mass=0.01"});
  });
  EXPECT_NE(message.find("needs effects.com_offset"), std::string::npos) << message;
  // without a slider section nothing moves and the offset parameter stays settable
  Simulation plain(loadSimulationConfig(path, {"motor.omega_rpm=0"}));
  EXPECT_EQ(plain.slider(), nullptr);
  plain.setParameter("effects.com_offset.offset", 2e-3);
  EXPECT_DOUBLE_EQ(plain.parameter("effects.com_offset.offset"), 2e-3);
}

// Elevation of the head axis t^0 above the horizontal [deg] (config: y up).
double headElevationDeg(const Simulation& sim) {
  const Vec3 axis = sim.sample().head_axis;
  return std::asin(std::clamp(axis.y() / axis.norm(), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(Slider, ComOffsetTiltsTheHeadBucklingKeepsItAndTheSliderFlipsIt) {
  // docs/model.md 5 and 7.4: with the COM 2 mm behind the COV along +t^0 the gravity couple turns
  // the swimming robot's axis down toward the vertical equilibrium; buckling pulses (40 rpm,
  // above the ~17 rpm threshold) reorient it only briefly; moving the slider 8 mm forward makes
  // l < 0 and turns the axis up (the other equilibrium), which buckling cannot do.
  std::vector<std::string> overrides = sliderOverrides();
  overrides.push_back("effects.com_offset.offset=2e-3");
  // the soft robot of the steering configs (r0 = 1.584 mm, spin-only head drag), which buckles
  // at 40 rpm; helical_robot.yaml is the source's stiffer Shore 32 robot
  overrides.push_back("robot.filament_radius=1.584e-3");
  overrides.push_back("effects.stokes_head.tilt_drag=0");
  const SimulationConfig config =
      loadSimulationConfig(std::string(kConfigDir) + "/helical_robot.yaml", overrides);
  Simulation sim(config);
  double pulse_end = -1.0;
  sim.setMotor(std::make_shared<CallbackMotor>([&](double t) {
    const double cruise = units::rpmToRadPerSec(10.0), buckle = units::rpmToRadPerSec(40.0);
    return std::min(t / 0.5, 1.0) * (t < pulse_end ? buckle : cruise);
  }));
  const double ratio = 0.012 / sim.parameter("effects.com_offset.head_mass");  // m_s / m_h
  const auto runFor = [&](double seconds) {
    const long steps = std::lround(seconds / config.dt);
    for (long k = 0; k < steps; ++k) sim.step();
  };
  runFor(5.0);
  const double settled = headElevationDeg(sim);
  EXPECT_LT(settled, -50.0);
  for (int pulse = 0; pulse < 3; ++pulse) {  // 1.5 s buckled, 1.5 s cruising
    pulse_end = sim.time() + 1.5;
    runFor(3.0);
  }
  const double after_pulses = headElevationDeg(sim);
  EXPECT_LT(after_pulses, -45.0);
  RecordProperty("elevation_after_pulses_deg", std::to_string(after_pulses));
  ASSERT_GT(ratio * 8e-3, 2e-3);  // the slider can reverse the sign of l
  sim.slider()->setTarget(-8e-3);
  runFor(10.0);
  EXPECT_LT(sim.parameter("effects.com_offset.offset"), 0.0);
  EXPECT_GT(headElevationDeg(sim), 45.0);
  RecordProperty("elevation_settled_deg", std::to_string(settled));
  RecordProperty("elevation_after_slider_deg", std::to_string(headElevationDeg(sim)));
}

}  // namespace
}  // namespace flagella
