// Open-loop replay of recorded commands (command_replay.h), the baseline of the steering
// robustness runs: commands come back by time, the end is reported, bad recordings are refused,
// step() does not allocate; and a closed-loop steering run recorded on the helical robot, replayed
// blind on the same model with the same sensors, retraces the same head path (the simulation is
// deterministic and the replay applies every command on the same step). A scored run that ends
// before the waypoints are placed counts every one of them missed. Reach times, the slider range
// and the model errors of the slider mass and the motor's torque constant.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "flagella_control/command_replay.h"
#include "flagella_control/steering_run.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/allocation_counter.h"

namespace flagella::control {
namespace {

ControllerInputs at(double t) {
  ControllerInputs in;
  in.time = t;
  in.imu_valid = true;
  return in;
}

TEST(CommandReplay, ReturnsTheCommandRecordedAtOrBeforeEachTime) {
  CommandReplayController replay({{0.0, 1.0, -1e-3}, {0.5, 2.0, 0.0}, {1.0, 0.0, 1e-3}}, -2e-3);
  const double start = 10.0;  // the replay's clock starts at its first step
  struct Expect {
    double t, motor, slider;
  };
  for (const Expect& e : {Expect{0.0, 1.0, -1e-3}, Expect{0.49, 1.0, -1e-3}, Expect{0.5, 2.0, 0.0},
                          Expect{0.99, 2.0, 0.0}, Expect{1.0, 0.0, 1e-3}}) {
    const ControllerOutputs out = replay.step(at(start + e.t));
    EXPECT_EQ(out.motor_command, e.motor) << "t = " << e.t;
    EXPECT_EQ(out.slider_position, e.slider) << "t = " << e.t;
    EXPECT_EQ(out.mode, ControllerMode::Running);
  }
  const ControllerOutputs after = replay.step(at(start + 1.01));
  EXPECT_TRUE(replay.finished());
  EXPECT_EQ(after.mode, ControllerMode::Finished);
  EXPECT_EQ(after.motor_command, 0.0);
  EXPECT_EQ(after.slider_position, -2e-3);
  replay.reset();
  EXPECT_FALSE(replay.finished());
  EXPECT_EQ(replay.step(at(3.0)).motor_command, 1.0);
}

TEST(CommandReplay, RefusesEmptyOrUnorderedRecordings) {
  EXPECT_THROW(CommandReplayController({}, 0.0), std::invalid_argument);
  EXPECT_THROW(CommandReplayController({{1.0, 0.0, 0.0}, {0.5, 0.0, 0.0}}, 0.0),
               std::invalid_argument);
}

TEST(CommandReplay, StepDoesNotAllocate) {
  std::vector<RecordedCommand> commands;
  for (int k = 0; k < 1000; ++k) commands.push_back({0.01 * k, 0.1 * k, 0.0});
  CommandReplayController replay(commands, 0.0);
  g_allocations = 0;
  g_count_allocations = true;
  for (int k = 0; k < 1200; ++k) replay.step(at(0.01 * k));
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(CommandReplay, ARecordedSteeringRunReplayedOnTheSameModelRetracesItsPath) {
  const std::string config_path = std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering.yaml";
  const flagella::SimulationConfig config = flagella::loadSimulationConfig(config_path, {});
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering.yaml");
  WaypointMission mission;
  mission.points = {Eigen::Vector3d(0.03, 0.0, 0.015)};  // a climb: the slider moves
  const flagella::SessionOptions sensors = steeringSessionOptions(config, calibration, 7);
  constexpr double kDuration = 12.0;  // [s]
  std::vector<RecordedCommand> recorded;
  MassTransformerController controller(mission, calibration);
  const SteeringRunResult closed =
      runSteering(config, sensors, controller, kDuration, 0.5, &recorded);
  ASSERT_GT(recorded.size(), 1000u);
  const SteeringRunResult open = runOpenLoop(config, sensors, recorded, calibration.park_position,
                                             closed.waypoints, mission.tolerance, kDuration);
  ASSERT_EQ(open.samples.size(), closed.samples.size());
  double largest = 0.0, slider_travel = 0.0;
  for (std::size_t i = 0; i < open.samples.size(); ++i) {
    largest = std::max(largest, (open.samples[i].position - closed.samples[i].position).norm());
    slider_travel =
        std::max(slider_travel, std::abs(closed.samples[i].slider - closed.samples.front().slider));
  }
  EXPECT_GT(slider_travel, 1e-4);  // the run exercised the slider, not only the motor
  EXPECT_LT(largest, 1e-9) << "head paths of the run and its replay differ";
  // The slider range is tracked every step: it holds every sampled position.
  for (const SteeringSample& s : closed.samples) {
    EXPECT_LE(closed.slider_low, s.slider);
    EXPECT_GE(closed.slider_high, s.slider);
  }
  EXPECT_EQ(open.slider_low, closed.slider_low);
  EXPECT_EQ(open.slider_high, closed.slider_high);
}

TEST(SteeringRun, ARunEndingBeforeTheWaypointsArePlacedCountsThemAllMissed) {
  // With course_time the waypoints are placed only after 30 s of cruise: a 1 s run must report
  // the mission's 4 waypoints as missed, not 0 of 0 reached.
  const std::string config_path = std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering.yaml";
  const flagella::SimulationConfig config = flagella::loadSimulationConfig(config_path, {});
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering.yaml");
  WaypointMission mission;
  mission.points.assign(4, Eigen::Vector3d(0.03, 0.0, 0.0));
  mission.course_time = 30.0;
  MassTransformerController controller(mission, calibration);
  const SteeringRunResult r =
      runSteering(config, steeringSessionOptions(config, calibration, 1), controller, 1.0);
  EXPECT_EQ(r.total, 4);
  EXPECT_EQ(r.reached, 0);
  ASSERT_EQ(r.miss.size(), 4u);
  for (double m : r.miss) EXPECT_TRUE(std::isinf(m));
  EXPECT_NE(steeringResultJson(r, "mass_transformer", "test").find("\"total\": 4"),
            std::string::npos);
}

TEST(SteeringRun, WaypointsPassedOutOfTurnCountAsReachedButNotInOrder) {
  // A straight cruise replayed open loop passes A (after 4 s) and then B (after 12 s). Scored
  // with the mission B, A both are reached, but only B in order: A was passed before B.
  const std::string config_path =
      std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering_source.yaml";
  const flagella::SimulationConfig config =
      flagella::loadSimulationConfig(config_path, {"robot.edge_length=0.015"});
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering_source.yaml");
  const flagella::SessionOptions sensors = steeringSessionOptions(config, calibration, 1);
  constexpr double kDuration = 14.0, kTolerance = 1e-3;  // [s], [m]
  const std::vector<RecordedCommand> cruise = {
      {0.0, calibration.cruise_omega, calibration.park_position},
      {kDuration, calibration.cruise_omega, calibration.park_position}};
  const Eigen::Vector3d far(1.0, 1.0, 1.0);
  const SteeringRunResult path =
      runOpenLoop(config, sensors, cruise, calibration.park_position, {far}, kTolerance, kDuration);
  const auto at = [&](double t) {
    for (const SteeringSample& s : path.samples)
      if (s.time >= t) return s;
    return path.samples.back();
  };
  const SteeringSample sample_a = at(4.0), sample_b = at(12.0);
  const Eigen::Vector3d a = sample_a.position, b = sample_b.position;
  ASSERT_GT((b - a).norm(), 5 * kTolerance);  // the robot moved on between them
  const SteeringRunResult wrong_order = runOpenLoop(
      config, sensors, cruise, calibration.park_position, {b, a}, kTolerance, kDuration);
  EXPECT_EQ(wrong_order.reached, 2);
  EXPECT_EQ(wrong_order.reached_in_order, 1);
  const SteeringRunResult right_order = runOpenLoop(
      config, sensors, cruise, calibration.park_position, {a, b}, kTolerance, kDuration);
  EXPECT_EQ(right_order.reached, 2);
  EXPECT_EQ(right_order.reached_in_order, 2);
  // Reach times: A within the tolerance no later than the sample it was taken from, B no later
  // than its own and after A; in the wrong order A (passed before B) has none.
  ASSERT_EQ(right_order.reach_time.size(), 2u);
  EXPECT_LE(right_order.reach_time[0], sample_a.time);
  EXPECT_LT(right_order.reach_time[0], right_order.reach_time[1]);
  EXPECT_LE(right_order.reach_time[1], sample_b.time);
  EXPECT_EQ(wrong_order.reach_time[0], right_order.reach_time[1]);
  EXPECT_TRUE(std::isnan(wrong_order.reach_time[1]));
  // Cruising at the park position the whole run: the slider range is that one position.
  EXPECT_DOUBLE_EQ(right_order.slider_low, calibration.park_position);
  EXPECT_DOUBLE_EQ(right_order.slider_high, calibration.park_position);
  EXPECT_EQ(right_order.motor_stop_retries, 0);
  EXPECT_NE(steeringResultJson(wrong_order, "replay", "test").find("\"reached_in_order\": 1"),
            std::string::npos);
}

TEST(SteeringRun, ModelErrorsOfTheSliderMassAndTheMotorTorqueConstantScaleTheirFields) {
  const std::string config_path = std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering.yaml";
  const flagella::SimulationConfig nominal = flagella::loadSimulationConfig(config_path, {});
  const auto wrong = [&](const std::vector<std::string>& base, const std::string& key) {
    return flagella::loadSimulationConfig(config_path,
                                          modelErrorOverrides(config_path, base, {{key, 1.3}}));
  };
  EXPECT_DOUBLE_EQ(wrong({}, "m_s").slider.mass, 1.3 * nominal.slider.mass);
  // The torque constant is the DC motor's stall torque (k_t V / R): scaled when the run has one.
  const std::vector<std::string> motor = {"effects.dc_motor.stall_torque=0.1"};
  EXPECT_NEAR(flagella::Simulation(wrong(motor, "k_t")).parameter("effects.dc_motor.stall_torque"),
              0.13, 1e-15);
  // Without one there is nothing to scale: the error names the key and the way to add it.
  try {
    modelErrorOverrides(config_path, {}, {{"k_t", 1.3}});
    ADD_FAILURE() << "k_t without a DC motor was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'k_t'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("effects.dc_motor"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flagella::control
