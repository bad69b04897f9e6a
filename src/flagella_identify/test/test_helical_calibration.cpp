// Calibration on helical-robot data, the source's workflow (docs/model.md 8.4.5): eps_ratio from a
// gimbal buckling threshold, and C_t and C_r of the head drag from an untethered speed and
// head-rate table, each made by the model at known values (a coarse discretisation keeps the runs
// short); the calibration starts elsewhere and must recover them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "flagella_identify/calibration.h"
#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"
#include "support/helical_test_baseline.h"

namespace flagella {
namespace identify {
namespace {

/// A coarse helical config with `overrides`: edges of 30 mm instead of 5 mm (about four per turn
/// of the helix). Truth and model share the discretisation, so the fits' recovery is what is
/// tested. Measured on 2026-11-30 alone on the 2-core machine, against 15 mm edges: the gimbal's
/// threshold 9.05 rpm (4.35), its fit 37 s (146 s), eps_ratio recovered to 0.3 % on both; the
/// head-drag fit 11 s (35 s beside another test).
YAML::Node coarseConfig(const std::string& name, std::vector<std::string> overrides) {
  overrides.push_back(testing::fastHelixEdges());
  return loadConfigTree(std::string(FLAGELLA_CONFIG_DIR) + "/" + name, overrides);
}

TEST(HelicalCalibration, HeadDragFromAnUntetheredSpeedAndHeadRateTable) {
  const double true_ct = 1.2, true_cr = 2.0;  // the config has 1.512 and 1.664
  SteadyStateTable table;
  table.settle_time = 20.0;
  table.window = 20.0;
  table.noise["v"] = 1e-5;                              // 0.01 mm/s
  table.noise["omega_h"] = units::rpmToRadPerSec(0.1);  // 0.1 rpm
  for (double rpm : {3.0, 6.0, 9.0}) {
    SimulationConfig cfg = parseSimulationConfig(
        coarseConfig("helical_robot.yaml",
                     {"effects.stokes_head.C_t=1.2", "effects.stokes_head.C_r=2.0"}),
        "truth");
    cfg.motor.mode = "constant";
    cfg.motor.omega = units::rpmToRadPerSec(rpm);
    cfg.duration = 40.0;
    cfg.steady_fraction = 0.5;
    Simulation sim(cfg);
    sim.run(cfg.duration);
    const SummaryMetrics m = sim.summary();
    ASSERT_FALSE(m.buckled) << rpm;  // below the threshold: a straight swimmer
    SteadyStateRow row;
    row.omega_T = cfg.motor.omega;
    row.measured["v"] = m.speed;
    row.measured["omega_h"] = m.omega_h;
    table.rows.push_back(row);
  }
  MeasuredData data;
  data.tables.push_back(table);

  CalibrationOptions options;
  options.free = {"effects.stokes_head.C_t", "effects.stokes_head.C_r"};
  options.evaluator.jobs = 2;
  const CalibrationResult r =
      calibrate(data, coarseConfig("helical_robot.yaml", {}), "helical_robot.yaml", options);
  ASSERT_EQ(r.parameters.size(), 2u);
  EXPECT_NEAR(r.parameters[0].value / true_ct, 1.0, 0.03) << r.parameters[0].value;
  EXPECT_NEAR(r.parameters[1].value / true_cr, 1.0, 0.03) << r.parameters[1].value;
  EXPECT_LT(r.quality.rms_z, 0.5);
  const YAML::Node calibrated = r.calibrated_config["effects"]["stokes_head"];
  EXPECT_DOUBLE_EQ(calibrated["C_t"].as<double>(), r.parameters[0].value);
}

/// A one-row gimbal threshold table holding `rpm` (the run length of the table does not enter
/// the model's growth-rate threshold).
MeasuredData gimbalThresholdTable(double rpm) {
  SteadyStateTable table;
  table.settle_time = 20.0;
  table.window = 20.0;
  table.noise["buckling_threshold"] = units::rpmToRadPerSec(0.1);
  SteadyStateRow row;
  row.measured["buckling_threshold"] = units::rpmToRadPerSec(rpm);
  table.rows.push_back(row);
  MeasuredData data;
  data.tables.push_back(table);
  return data;
}

TEST(HelicalCalibration, RegularisationFromAGimbalBucklingThreshold) {
  const double true_ratio = 1.0;  // the default is sqrt(e) = 1.65
  const YAML::Node truth = coarseConfig("helical_gimbal.yaml", {"effects.rss.eps_ratio=1.0"});
  // The truth's threshold: where the growth rate of the slow tilt changes sign (docs/model.md
  // 8.4.4), found by the tool's search; the evaluator's threshold searched from it must agree.
  const SimulationConfig cfg = parseSimulationConfig(truth, "truth");
  GrowthThresholdOptions search;
  search.low = 4.0;
  search.high = 16.0;
  const GrowthProbeOptions probe;
  const GrowthThreshold direct =
      findGrowthThreshold([&](double rpm) { return runGrowthProbe(cfg, rpm, probe); }, search);
  ASSERT_TRUE(direct.found) << direct.message;
  const Model at_truth(truth, "truth", {"effects.rss.eps_ratio"});
  // The config's Newton tolerance (the evaluator's default 1e-7 is for smooth Jacobians; a
  // derivative-free fit does not need it and runs 1.5x faster without).
  EvaluatorOptions evaluator;
  evaluator.solver_tolerance = cfg.solver.residual_tolerance;
  evaluator.jobs = 2;  // the two first bracketing points at once
  const MeasuredData data = gimbalThresholdTable(direct.threshold);
  const Evaluation e = Evaluator(data, trainingOnlySplit(data), evaluator)
                           .evaluate(at_truth, at_truth.values(), Part::kAll);
  ASSERT_TRUE(e.ok) << e.failure;
  const double rpm = e.points.at(0).model * units::kRpmPerRadPerSec;
  std::printf("truth's threshold: %.4f +- %.4f rpm from 4-16 rpm, %.4f rpm from x/1.3 of it\n",
              direct.threshold, direct.uncertainty, rpm);
  EXPECT_NEAR(rpm, direct.threshold, 0.01 * direct.threshold);
  CalibrationOptions options;
  options.free = {"effects.rss.eps_ratio"};
  options.evaluator = evaluator;
  options.fit.progress = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  const CalibrationResult r =
      calibrate(data, coarseConfig("helical_gimbal.yaml", {}), "helical_gimbal.yaml", options);
  EXPECT_EQ(r.fit.method, "Brent");
  ASSERT_EQ(r.parameters.size(), 1u);
  EXPECT_NEAR(r.start[0].value, std::sqrt(std::exp(1.0)), 1e-12);
  // Brent narrows log eps_ratio to a bracket of about 0.04.
  EXPECT_NEAR(r.parameters[0].value / true_ratio, 1.0, 0.05) << r.parameters[0].value;
  EXPECT_LT(std::abs(r.parameters[0].value - true_ratio), 3.0 * r.parameters[0].uncertainty)
      << "+- " << r.parameters[0].uncertainty;
  EXPECT_LT(r.quality.rms_z, 0.5);
}

TEST(HelicalCalibration, AFreeParameterWhoseDefaultDependsOnTheRobotNeedsAStartValue) {
  MeasuredData data;
  CalibrationOptions options;
  options.free = {"effects.rss.eps"};
  try {
    calibrate(data, coarseConfig("helical_gimbal.yaml", {}), "helical_gimbal.yaml", options);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--set effects.rss.eps=VALUE"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace identify
}  // namespace flagella
