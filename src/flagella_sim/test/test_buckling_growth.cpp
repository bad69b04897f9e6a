// The growth rate of the flagellum's slow tilt (docs/model.md 8.4.4) on the gimbal robot, coarse
// (edges of 15 mm): its sign at a rate below and one above the threshold, checked against runs
// four times as long that show directly what happens (the tilt dies out, or the flagellum buckles
// past 15 deg); and the shipped configs of the source's robots load with the head resisting pitch.
#include <gtest/gtest.h>

#include <cmath>

#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;

// 0.8 and 1.2 times the coarse gimbal's threshold (3.78 rpm by flagella_buckling)
constexpr double kBelow = 3.0, kAbove = 4.5;  // [rpm]

SimulationConfig coarseGimbal() {
  return loadSimulationConfig(std::string(kConfigDir) + "/helical_gimbal.yaml",
                              {"robot.edge_length=0.015"});
}

// The largest tilt [deg] in the first and in the last `share` of a direct run of `seconds`.
std::pair<double, double> earlyAndLateTilt(double rpm, double seconds, double share) {
  SimulationConfig c = coarseGimbal();
  c.motor.omega = units::rpmToRadPerSec(rpm);
  Simulation sim(c);
  sim.run(seconds);
  double early = 0.0, late = 0.0;
  for (const TrajectorySample& s : sim.trajectory()) {
    if (s.time <= share * seconds) early = std::max(early, s.flagellum_tilt);
    if (s.time >= (1.0 - share) * seconds) late = std::max(late, s.flagellum_tilt);
  }
  return {units::radToDeg(early), units::radToDeg(late)};
}

TEST(BucklingGrowth, SignOfTheGrowthRateMatchesWhatLongRunsShow) {
  const GrowthProbeOptions options;  // 8 turns, settled over 3
  for (double rpm : {kBelow, kAbove}) {
    const GrowthProbe p = runGrowthProbe(coarseGimbal(), rpm, options);
    ASSERT_FALSE(p.failed) << p.error;
    EXPECT_TRUE(p.trusted()) << rpm << " rpm: sigma " << p.sigma << " +- " << p.sigma_error;
    std::printf("%.2f rpm: sigma %+.4f +- %.4f 1/s, turn %.1f s\n", rpm, p.sigma, p.sigma_error,
                p.period);
    // four times as long as the probe (its turn: the gimbal's flagellum turns with the motor)
    const double seconds = 4.0 * options.observe_turns * 60.0 / rpm;
    const auto [early, late] = earlyAndLateTilt(rpm, seconds, 0.25);
    std::printf("  direct run of %.0f s: largest tilt %.2f deg early, %.2f deg late\n", seconds,
                early, late);
    if (rpm == kBelow) {
      EXPECT_LT(p.sigma, 0.0);
      EXPECT_LT(late, early);  // the spin-up's lean dies out, the straight state's own stays
      EXPECT_LT(late, 15.0);   // straight
    } else {
      EXPECT_GT(p.sigma, 0.0);
      EXPECT_GT(late, 15.0);  // buckled
    }
  }
}

TEST(BucklingGrowth, TheSourceRobotsLoadWithTheirModuliAndAPitchResistingHead) {
  const std::pair<const char*, double> robots[] = {{"helical_pla.yaml", 4.107e9},
                                                   {"helical_shore32.yaml", 1.225e6},
                                                   {"helical_shore22.yaml", 0.77e6},
                                                   {"helical_robot.yaml", 1.225e6}};
  double radius = 0.0, c_t = 0.0, c_r = 0.0;
  for (const auto& [name, modulus] : robots) {
    const SimulationConfig c = loadSimulationConfig(std::string(kConfigDir) + "/" + name);
    ASSERT_EQ(c.robotType(), "helical") << name;
    EXPECT_EQ(c.robotGeometry<HelicalGeometry>().flagellum.youngs_modulus, modulus) << name;
    EXPECT_EQ(c.robotGeometry<HelicalGeometry>().pitch_count, 3.5) << name;
    if (radius == 0.0) radius = c.robotGeometry<HelicalGeometry>().flagellum.radius;
    EXPECT_EQ(c.robotGeometry<HelicalGeometry>().flagellum.radius, radius)
        << name << ": one mould for all";
    Simulation sim(c);
    EXPECT_EQ(sim.parameter("effects.stokes_head.tilt_drag"), 1.0) << name;
    // One head, one pair of coefficients, fitted with the configs' one eps (docs/model.md 8.4.1).
    if (c_t == 0.0) c_t = sim.parameter("effects.stokes_head.C_t");
    if (c_r == 0.0) c_r = sim.parameter("effects.stokes_head.C_r");
    EXPECT_EQ(sim.parameter("effects.stokes_head.C_t"), c_t) << name;
    EXPECT_EQ(sim.parameter("effects.stokes_head.C_r"), c_r) << name;
    EXPECT_DOUBLE_EQ(sim.parameter("effects.rss.eps_ratio"), std::sqrt(std::exp(1.0))) << name;
  }
  const SimulationConfig three = loadSimulationConfig(
      std::string(kConfigDir) + "/helical_shore22.yaml", {"robot.pitch_count=3"});
  EXPECT_EQ(three.robotGeometry<HelicalGeometry>().pitch_count, 3.0);
}

}  // namespace
}  // namespace flagella
