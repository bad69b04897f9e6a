// The small fast cases of the steering robustness runs (steering_robustness.h; the full runs are
// flagella_steer_robustness's): one seeded run on each steering robot with its model wrong by
// +-20 % in eps, E, C_t, C_r and l_0, on its demo mission's first leg, a climb. The closed loop
// must reach the waypoint; the open-loop schedule the controller gave on the nominal model with
// perfect sensors, replayed blind on the same wrong model, must miss it (the wrong model moves the
// slider's neutral, and the replayed slider positions pitch the robot away).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/steering_robustness.h"

namespace flagella::control {
namespace {

// Seed 1's wrong model only (no nominal closed loop), closed loop and replay at once.
RobustnessOptions oneWrongModelRun(const std::string& config_name, double max_duration) {
  RobustnessOptions options;
  options.config_path = std::string(FLAGELLA_CONFIG_DIR) + "/" + config_name;
  options.runs = 1;
  options.first_seed = 1;
  options.nominal = false;
  options.jobs = 2;
  options.max_duration = max_duration;
  return options;
}

// The report of oneWrongModelRun: the nominal reference reached the waypoint; the closed loop
// and the replay ran on the same wrong model, every key off by options.error one way or the
// other; the closed loop reached the waypoint without a halt and the replay did not.
void expectTheClosedLoopReachesWhatTheReplayMisses(const RobustnessReport& report,
                                                   const RobustnessOptions& options) {
  ASSERT_EQ(report.references.at(0).reached, 1) << "the nominal run itself misses the climb";
  ASSERT_EQ(report.runs.size(), 2u);
  const RobustnessRun& closed = report.runs[0];
  const RobustnessRun& open = report.runs[1];
  ASSERT_EQ(closed.kind, "mismatched closed");
  ASSERT_EQ(open.kind, "mismatched open");
  ASSERT_TRUE(closed.error.empty()) << closed.error;
  ASSERT_TRUE(open.error.empty()) << open.error;
  EXPECT_EQ(closed.factors, open.factors);
  ASSERT_EQ(closed.factors.size(), options.keys.size());
  for (const auto& [key, factor] : closed.factors)
    EXPECT_NEAR(std::abs(factor - 1.0), options.error, 1e-12) << key;
  EXPECT_FALSE(closed.result.halted) << closed.result.halt_reason;
  EXPECT_EQ(closed.result.reached, 1)
      << "closed loop missed by " << 1e3 * closed.result.max_miss << " mm";
  EXPECT_EQ(open.result.reached, 0)
      << "open loop passed within " << 1e3 * open.result.max_miss << " mm";
}

TEST(SteeringRobustness, OnAWrongModelTheClosedLoopReachesAClimbThatTheNominalScheduleMisses) {
  // [s]; the demo's runs reach the climb at 65-105 s
  const RobustnessOptions options = oneWrongModelRun("helical_steering.yaml", 200.0);
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering.yaml");
  WaypointMission mission;  // the demo's first leg (config/paths/steering_demo.yaml)
  mission.points = {Eigen::Vector3d(0.030, -0.008, 0.012)};  // 21 deg up, 15 deg right
  mission.course_time = 30.0;  // [s] of straight cruise give the start frame's x
  const RobustnessReport report = runRobustness(options, calibration, mission, SteeringGains{});

  ASSERT_NO_FATAL_FAILURE(expectTheClosedLoopReachesWhatTheReplayMisses(report, options));
  const RobustnessRun& closed = report.runs[0];
  const RobustnessRun& open = report.runs[1];
  EXPECT_GT(open.result.max_miss, closed.result.max_miss);
  std::printf("closed loop: miss %.1f mm at %.0f s; open loop: miss %.1f mm (tolerance %.0f mm)\n",
              1e3 * closed.result.max_miss, closed.result.time, 1e3 * open.result.max_miss,
              1e3 * mission.tolerance);
}

// The source's steering robot with its shipped calibration and the turns-in-place gains
// (helical_steering_source_reorient_gains.yaml: the slider 1.5 mm off park with the motor at
// 20 rpm forward or reversed, no buckle cycles): seed 4's wrong model (E 20 % high; eps, C_t,
// C_r, l_0 20 % low; the model whose buckle cycles turn least predictably) on the restored
// demo's first leg, a climb of 30 deg over 100 mm. The closed loop must pass it within the
// tolerance; the nominal schedule replayed blind must not (the wrong model pitches and turns at
// other rates, so the same turns in place point it elsewhere).
TEST(SteeringRobustness, OnTheSourceRobotAWrongModelsTurnsInPlacePassTheClimbTheScheduleMisses) {
  // [s]; this model's closed loop passes the climb at about 171 s, the nominal one at 110 s
  RobustnessOptions options = oneWrongModelRun("helical_steering_source.yaml", 200.0);
  options.first_seed = 4;
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering_source.yaml");
  SteeringGains gains;
  gains.load(std::string(FLAGELLA_CONFIG_DIR) +
             "/calibration/helical_steering_source_reorient_gains.yaml");
  gains.validate();
  ASSERT_TRUE(gains.reorient);
  WaypointMission mission;  // the restored demo's first leg (config/paths/source/demo.yaml)
  mission.points = {Eigen::Vector3d(0.121, 0.0, 0.050)};
  mission.tolerance = 0.018;   // [m], half a head length
  mission.course_time = 30.0;  // [s] of straight cruise give the start frame's x
  const RobustnessReport report = runRobustness(options, calibration, mission, gains);

  ASSERT_NO_FATAL_FAILURE(expectTheClosedLoopReachesWhatTheReplayMisses(report, options));
  const RobustnessRun& closed = report.runs[0];
  const RobustnessRun& open = report.runs[1];
  std::printf(
      "source robot, turns in place: closed loop: miss %.1f mm, reached at %.0f s; open loop: "
      "miss %.1f mm\n",
      1e3 * closed.result.max_miss, closed.result.reach_time.at(0), 1e3 * open.result.max_miss);
}

// A mission set without the replay: no reference run, one closed loop per mission and seed, the
// seed's wrong model the same in every mission. Cut at 31 s simulated (the missions' 30 s of
// straight cruise place their waypoints at 30 s); what the runs reach is not the point here.
TEST(SteeringRobustness, AMissionSetWithoutReplayRunsEachMissionOnEachSeedsWrongModel) {
  RobustnessOptions options = oneWrongModelRun("helical_steering_source.yaml", 31.0);
  options.runs = 2;
  options.replay = false;
  const SteeringCalibration calibration = loadSteeringCalibration(
      std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering_source.yaml");
  WaypointMission ahead, climb;
  ahead.points = {Eigen::Vector3d(0.100, 0.0, 0.0)};
  climb.points = {Eigen::Vector3d(0.087, 0.0, 0.050)};
  ahead.course_time = climb.course_time = 30.0;
  ahead.tolerance = climb.tolerance = 0.018;
  const RobustnessReport report =
      runRobustness(options, calibration, {{"ahead", ahead}, {"climb", climb}}, SteeringGains{});

  EXPECT_TRUE(report.references.empty());
  EXPECT_EQ(report.missions, (std::vector<std::string>{"ahead", "climb"}));
  ASSERT_EQ(report.runs.size(), 4u);  // 2 missions x 2 seeds, closed loop only
  std::map<unsigned, std::vector<std::pair<std::string, double>>> factors_of_seed;
  for (std::size_t k = 0; k < report.runs.size(); ++k) {
    const RobustnessRun& run = report.runs[k];
    EXPECT_EQ(run.kind, "mismatched closed");
    EXPECT_EQ(run.mission, k / 2);
    EXPECT_EQ(run.seed, options.first_seed + k % 2);
    EXPECT_TRUE(run.error.empty()) << run.error;
    EXPECT_EQ(run.result.total, 1);
    EXPECT_EQ(run.factors, drawModelErrors(options, run.seed));
    if (!factors_of_seed.count(run.seed)) factors_of_seed[run.seed] = run.factors;
    EXPECT_EQ(run.factors, factors_of_seed[run.seed]) << "seed " << run.seed;
  }
  EXPECT_NE(factors_of_seed[1], factors_of_seed[2]);  // seeds 1 and 2 draw different signs
}

// The set's tables count what the runs reached: a synthetic report (no simulation) in which seed
// 1 passes "ahead" and misses "climb" (1 of 2 waypoints), seed 2 passes both.
TEST(SteeringRobustness, TheSetSummaryCountsMissionsPerMissionAndPerSeed) {
  RobustnessReport report;
  report.missions = {"ahead", "climb"};
  report.tolerances = {0.018, 0.018};
  auto run = [](std::size_t mission, unsigned seed, int reached, double worst) {
    RobustnessRun r;
    r.kind = "mismatched closed";
    r.mission = mission;
    r.seed = seed;
    r.result.total = 2;
    r.result.reached = r.result.reached_in_order = reached;
    r.result.miss = {0.005, worst};
    r.result.max_miss = worst;
    return r;
  };
  report.runs = {run(0, 1, 2, 0.010), run(1, 1, 1, 0.050), run(0, 2, 2, 0.012),
                 run(1, 2, 2, 0.015)};
  const std::string summary = robustnessSummary(report);
  std::printf("%s", summary.c_str());
  // all runs: 3 of 4 succeed, 7 of 8 waypoints; worst miss 50.0 mm
  EXPECT_NE(summary.find("mismatched closed      4       75%      7 of 8"), std::string::npos);
  EXPECT_NE(summary.find("ahead              mismatched closed      2    2 of 2        4 of 4"),
            std::string::npos);
  EXPECT_NE(summary.find("climb              mismatched closed      2    1 of 2        3 of 4"),
            std::string::npos);
  EXPECT_NE(summary.find("50.0 mm"), std::string::npos);
  EXPECT_NE(summary.find("seed 1      1 of 2 (missed: climb)"), std::string::npos);
  EXPECT_NE(summary.find("seed 2      2 of 2\n"), std::string::npos);
  const std::string json = robustnessJson(report);
  EXPECT_NE(json.find("{\"name\": \"climb\", \"tolerance_mm\": 18, \"reference\": null}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"mission\": \"climb\", \"seed\": 2"), std::string::npos) << json;
}

}  // namespace
}  // namespace flagella::control
