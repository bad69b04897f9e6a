// Discretisation convergence of the steady-state metrics (docs/model.md 7.1) in time step and edge
// length, for the granular design 1 robot (docs/model.md 8.1, n = 2, 100 rpm) and the interface
// robot (docs/model.md 8.3).
//
// Halving dt (0.01 -> 0.005 s) and halving the tail edge length (27 -> 54 edges for design 1,
// 28 -> 56 for the interface robot) must change the summary metrics by less than the stated
// tolerances. For design 1 the sequence is continued one more level (dt/4, edges x4) to show the
// trend: implicit Euler is first order in dt, and the clamped tail root makes the deflection first
// order in the edge length (the rigid root spring holds the first tail edge, so the effective
// clamp sits about half an edge from the disc), so each halving should roughly halve the change.
//
// The measured relative changes are printed so they can be reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace {

// ---- run lengths ----------------------------------------------------------------------------
// Design 1 settles in ~15 s (first-mode tail relaxation eta_p L^4 / (1.875^4 EI) = 27.8 s / 12.4
// = 2.2 s, five of them plus the ramp); the summary uses 20..40 s.
constexpr double kDesign1Duration = 40.0;
// The interface robot settles in ~2 s; the summary uses 6..30 s (about 2.7 rad of circle).
constexpr double kInterfaceDuration = 30.0;
constexpr double kInterfaceSteadyFraction = 0.8;

// ---- tolerances (relative changes of a metric when halving dt or the edge length) -------------
// dt 0.01 -> 0.005 s. Measured: design 1 <= 0.09 % (omega_t), interface <= 0.16 % (omega_t).
// Implicit Euler's O(dt) error is small because the motor turns only 0.1 rad per step; 0.5 %.
constexpr double kTimeStepTolerance = 0.005;
// Edge length halved. Measured: design 1 3.2 % (omega_t) and 3.4 % (speed); the interface robot
// 1.5 % (omega_t), 1.1 % (omega_h), 0.9 % (yaw rate), 0.1 % (radius). The first-order clamp error
// (deflection ~ (L - h/2)^4, i.e. -2h/L = -7 % at 27 edges, halved by halving h) dominates.
// 5 % for design 1 (whose speed is proportional to the deflection), 3 % for the interface robot.
constexpr double kDesign1EdgeTolerance = 0.05;
constexpr double kInterfaceEdgeTolerance = 0.03;
// Trend: ratio of successive changes (coarse->mid over mid->fine). First-order convergence gives 2
// (measured 2.0 in dt and 1.9-2.2 in edges); anything above 1.4 shows the sequence converging
// at better than ~half order, below 2.8 rules out a faster-than-first-order artefact.
constexpr double kMinConvergenceRatio = 1.4;
constexpr double kMaxConvergenceRatio = 2.8;
// Metrics whose dt change is below this are at the level of the Newton tolerance and are not used
// for the trend (design 1 speed changes by ~1e-5 relative when halving dt).
constexpr double kResolvableChange = 1e-4;

std::string configPath(const std::string& file) {
  return std::string(FLAGELLA_CONFIG_DIR) + "/" + file;
}

struct Metric {
  std::string name;
  std::function<double(const SummaryMetrics&)> get;
};

const std::vector<Metric>& design1Metrics() {
  static const std::vector<Metric> metrics{
      {"omega_h", [](const SummaryMetrics& m) { return m.omega_h; }},
      {"omega_t", [](const SummaryMetrics& m) { return m.omega_t; }},
      {"speed", [](const SummaryMetrics& m) { return m.speed; }}};
  return metrics;
}

const std::vector<Metric>& interfaceMetrics() {
  static const std::vector<Metric> metrics{
      {"omega_h", [](const SummaryMetrics& m) { return m.omega_h; }},
      {"omega_t", [](const SummaryMetrics& m) { return m.omega_t; }},
      {"yaw_rate", [](const SummaryMetrics& m) { return m.yaw_rate; }},
      {"circle_radius", [](const SummaryMetrics& m) { return m.circle_radius; }}};
  return metrics;
}

SummaryMetrics simulate(SimulationConfig config, const std::string& label) {
  const auto start = std::chrono::steady_clock::now();
  Simulation sim(config);
  sim.run(config.duration);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[convergence] %-28s dt %.4g s, %3d edges/tail: wall %.1f s\n", label.c_str(),
              config.dt, config.robotGeometry<MultiTailGeometry>().tail_edges, wall);
  return sim.summary();
}

// Newton solved far below the default tolerance, so the changes measured here are
// discretisation error only (the default 1e-4 moves the metrics by ~1e-5 relative).
const char* const kTightNewton = "solver.residual_tolerance=1e-9";

SimulationConfig design1(double dt, int tail_edges) {
  SimulationConfig c = loadSimulationConfig(
      configPath("granular_design1.yaml"),
      {"robot.n_tails=2", "motor.omega_rpm=100", "simulation.steady_fraction=0.5",
       "simulation.duration=" + std::to_string(kDesign1Duration), kTightNewton});
  c.dt = dt;
  c.editRobotGeometry<MultiTailGeometry>().tail_edges = tail_edges;
  return c;
}

SimulationConfig interfaceRobot(double dt, int tail_edges) {
  SimulationConfig c = loadSimulationConfig(
      configPath("interface_robot.yaml"),
      {"simulation.duration=" + std::to_string(kInterfaceDuration),
       "simulation.steady_fraction=" + std::to_string(kInterfaceSteadyFraction), kTightNewton});
  c.dt = dt;
  c.editRobotGeometry<MultiTailGeometry>().tail_edges =
      tail_edges;  // the config's 4 mm edges give 28 (0.11 m / 4 mm rounded)
  return c;
}

double relChange(double coarse, double fine) { return std::abs(fine - coarse) / std::abs(fine); }

// Prints and checks |fine - coarse| / |fine| < tolerance for every metric; returns the changes.
std::vector<double> expectSmallChanges(const std::vector<Metric>& metrics,
                                       const SummaryMetrics& coarse, const SummaryMetrics& fine,
                                       double tolerance, const std::string& what) {
  std::vector<double> changes;
  for (const Metric& m : metrics) {
    const double a = m.get(coarse), b = m.get(fine), change = relChange(a, b);
    std::printf("[convergence] %-34s %-14s %.8g -> %.8g  relative change %.3e (tolerance %.1e)\n",
                what.c_str(), m.name.c_str(), a, b, change, tolerance);
    EXPECT_TRUE(std::isfinite(a) && std::isfinite(b)) << what << " " << m.name;
    EXPECT_LT(change, tolerance) << what << " " << m.name;
    changes.push_back(change);
  }
  return changes;
}

void expectFirstOrderTrend(const std::vector<Metric>& metrics, const std::vector<double>& first,
                           const std::vector<double>& second, const std::string& what) {
  int checked = 0;
  for (size_t i = 0; i < metrics.size(); ++i) {
    const double ratio = first[i] / second[i];
    std::printf("[convergence] %-34s %-14s change ratio %.3f\n", what.c_str(),
                metrics[i].name.c_str(), ratio);
    if (first[i] < kResolvableChange) continue;
    ++checked;
    EXPECT_GT(ratio, kMinConvergenceRatio) << what << " " << metrics[i].name;
    EXPECT_LT(ratio, kMaxConvergenceRatio) << what << " " << metrics[i].name;
  }
  EXPECT_GT(checked, 0) << what << ": no metric changed enough to show a trend";
}

TEST(Convergence, Design1TimeStep) {
  const SummaryMetrics m1 = simulate(design1(0.01, 27), "design 1");
  const SummaryMetrics m2 = simulate(design1(0.005, 27), "design 1");
  const SummaryMetrics m4 = simulate(design1(0.0025, 27), "design 1");
  const auto c12 =
      expectSmallChanges(design1Metrics(), m1, m2, kTimeStepTolerance, "design 1 dt 0.01 -> 0.005");
  const auto c24 = expectSmallChanges(design1Metrics(), m2, m4, kTimeStepTolerance,
                                      "design 1 dt 0.005 -> 0.0025");
  expectFirstOrderTrend(design1Metrics(), c12, c24, "design 1 dt trend");
}

TEST(Convergence, Design1EdgeLength) {
  const SummaryMetrics e27 = simulate(design1(0.01, 27), "design 1");
  const SummaryMetrics e54 = simulate(design1(0.01, 54), "design 1");
  const SummaryMetrics e108 = simulate(design1(0.01, 108), "design 1");
  const auto c1 = expectSmallChanges(design1Metrics(), e27, e54, kDesign1EdgeTolerance,
                                     "design 1 edges 27 -> 54");
  const auto c2 = expectSmallChanges(design1Metrics(), e54, e108, kDesign1EdgeTolerance,
                                     "design 1 edges 54 -> 108");
  expectFirstOrderTrend(design1Metrics(), c1, c2, "design 1 edge trend");
}

TEST(Convergence, InterfaceRobotTimeStepAndEdgeLength) {
  const SummaryMetrics base = simulate(interfaceRobot(0.01, 28), "interface");
  const SummaryMetrics half_dt = simulate(interfaceRobot(0.005, 28), "interface");
  const SummaryMetrics half_dl = simulate(interfaceRobot(0.01, 56), "interface");
  ASSERT_TRUE(base.circle_valid && half_dt.circle_valid && half_dl.circle_valid);
  expectSmallChanges(interfaceMetrics(), base, half_dt, kTimeStepTolerance,
                     "interface dt 0.01 -> 0.005");
  expectSmallChanges(interfaceMetrics(), base, half_dl, kInterfaceEdgeTolerance,
                     "interface edges 28 -> 56");
}

}  // namespace
}  // namespace flagella
