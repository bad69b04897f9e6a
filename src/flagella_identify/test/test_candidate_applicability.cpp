// Which candidates and discovery cases apply to which robot: a granular yield or stick-slip acts
// only in the granular medium (resistive force theory in the config), a tail asymmetry only on a
// robot with two tails or more; a single-flagellum swimmer gets the table and track cases of the
// effects that act on it, on its own plans of motor rates and with its own realistic strengths
// (docs/model.md 7.6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <vector>

#include "flagella_identify/candidates.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/model.h"
#include "flagella_identify/power_check.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/outputs/fits.h"

namespace flagella {
namespace identify {
namespace {

YAML::Node baseline(const std::string& name) {
  return loadConfigTree(std::string(FLAGELLA_CONFIG_DIR) + "/identification/" + name, {});
}

const char* kGranular = "granular_design1_coarse.yaml";
const char* kHelical = "helical_shore32_coarse.yaml";

TEST(CandidateApplicability, GranularEffectsNeedTheGranularMediumsResistiveForceTheory) {
  for (const std::string name : {"granular_yield", "granular_jamming"}) {
    EXPECT_EQ(notApplicableReason(candidateByName(name), baseline(kGranular)), "") << name;
    const std::string reason = notApplicableReason(candidateByName(name), baseline(kHelical));
    EXPECT_NE(reason.find("effects.rft"), std::string::npos) << name << ": " << reason;
  }
}

TEST(CandidateApplicability, TailWeightNeedsAFlagellumSwimmingInALiquid) {
  const Candidate& c = candidateByName("tail_weight");
  EXPECT_EQ(notApplicableReason(c, baseline(kHelical)), "");
  const std::string reason = notApplicableReason(c, baseline(kGranular));
  EXPECT_NE(reason.find("effects.rss"), std::string::npos) << reason;
}

TEST(CandidateApplicability, TailAsymmetryNeedsTwoTails) {
  const Candidate& c = candidateByName("fabrication_asymmetry");
  EXPECT_EQ(tailCountOf(baseline(kGranular)), 2);
  EXPECT_EQ(tailCountOf(baseline(kHelical)), 1);
  EXPECT_EQ(notApplicableReason(c, baseline(kGranular)), "");
  EXPECT_NE(notApplicableReason(c, baseline(kHelical)).find("1 tail"), std::string::npos);
}

// docs/model.md 8.4.1, 3.1: only a helical flagellum has a hook, and only a head whose pitch and
// yaw drag the config models can have it scaled.
TEST(CandidateApplicability, HookAndHeadTiltDragNeedTheHelicalRobot) {
  for (const std::string name : {"hook_stiffness", "head_tilt_drag"}) {
    const Candidate& c = candidateByName(name);
    EXPECT_EQ(notApplicableReason(c, baseline(kHelical)), "") << name;
    EXPECT_NE(notApplicableReason(c, baseline(kGranular)), "") << name;
  }
  EXPECT_NE(candidateByName("hook_stiffness").needs & kTilt, 0u);          // a table with the tilt
  EXPECT_NE(candidateByName("head_tilt_drag").needs & kTimeResolved, 0u);  // a head track
  EXPECT_NE(notApplicableReason(candidateByName("hook_stiffness"), baseline(kGranular))
                .find("robot.type multi_tail"),
            std::string::npos);
  EXPECT_NE(notApplicableReason(candidateByName("head_tilt_drag"), baseline(kGranular))
                .find("effects.stokes_head.tilt_drag"),
            std::string::npos);
  // a config without the head's Stokes drag at all gets the same reason, not an exception
  YAML::Node without_head_drag = baseline(kHelical);
  without_head_drag["effects"].remove("stokes_head");
  EXPECT_NE(notApplicableReason(candidateByName("head_tilt_drag"), without_head_drag)
                .find("effects.stokes_head.tilt_drag"),
            std::string::npos);
}

// The fitted ratio multiplies what the baseline has, and the off value 1 leaves it alone.
TEST(CandidateApplicability, HookAndHeadTiltDragScaleTheBaselinesFields) {
  YAML::Node cfg = baseline(kHelical);
  cfg["robot"]["hook_stiffness_scale"] = 3.0;
  cfg["effects"]["stokes_head"]["tilt_drag"] = 1.5;
  YAML::Node off = YAML::Clone(cfg);
  candidateByName("hook_stiffness").apply(off, {1.0}, 0.0);
  candidateByName("head_tilt_drag").apply(off, {1.0}, 0.0);
  EXPECT_EQ(off["robot"]["hook_stiffness_scale"].as<double>(), 3.0);
  EXPECT_EQ(off["effects"]["stokes_head"]["tilt_drag"].as<double>(), 1.5);
  candidateByName("hook_stiffness").apply(cfg, {0.5}, 0.0);
  candidateByName("head_tilt_drag").apply(cfg, {2.0}, 0.0);
  EXPECT_DOUBLE_EQ(cfg["robot"]["hook_stiffness_scale"].as<double>(), 1.5);
  EXPECT_DOUBLE_EQ(cfg["effects"]["stokes_head"]["tilt_drag"].as<double>(), 3.0);
}

TEST(CandidateApplicability, MotorAndMediumEffectsApplyToEveryRobot) {
  for (const std::string name : {"dc_motor", "viscosity_drift", "com_offset"})
    for (const char* robot : {kGranular, kHelical})
      EXPECT_EQ(notApplicableReason(candidateByName(name), baseline(robot)), "")
          << name << " on " << robot;
}

TEST(CandidateApplicability, EveryCaseButTheSwimmersAppliesToTheGranularRobot) {
  for (const DiscoveryCase& c : discoveryCases())
    if (c.name == "tail_weight" || c.name == "hook_stiffness" || c.name == "head_tilt_drag")
      EXPECT_NE(caseNotApplicableReason(c, baseline(kGranular)), "") << c.name;
    else
      EXPECT_EQ(caseNotApplicableReason(c, baseline(kGranular)), "") << c.name;
}

TEST(CandidateApplicability, TheSingleFlagellumRobotGetsTheCasesOfItsEffects) {
  std::set<std::string> applicable;
  for (const DiscoveryCase& c : discoveryCases())
    if (caseNotApplicableReason(c, baseline(kHelical)).empty()) applicable.insert(c.name);
  EXPECT_EQ(applicable,
            (std::set<std::string>{"null_table", "null_series", "dc_motor", "viscosity_drift",
                                   "interface_lateral_force", "com_offset", "tail_weight",
                                   "hook_stiffness", "head_tilt_drag", "unknown_ripple"}));
  EXPECT_THROW(
      generateCase(discoveryCaseByName("strong_lateral_2_tails"), baseline(kHelical), kHelical, 1),
      std::invalid_argument);
}

TEST(CandidateApplicability, StrengthsFollowTheRobot) {
  // the helical robot's slowly spinning head needs a larger surface coefficient to show, and
  // its whole body pitches under a far smaller head offset than design 1's
  for (const std::string name : {"interface_lateral_force", "com_offset"}) {
    const Candidate& c = candidateByName(name);
    const std::vector<TypicalStrength>& tailed = typicalStrengths(c, baseline(kGranular));
    const std::vector<TypicalStrength>& single = typicalStrengths(c, baseline(kHelical));
    ASSERT_EQ(tailed.size(), 1u);
    ASSERT_EQ(single.size(), 1u);
    EXPECT_EQ(tailed[0].low, c.typical[0].low) << name;
    EXPECT_NE(single[0].low, tailed[0].low) << name;
  }
  const Candidate& motor = candidateByName("dc_motor");  // no robot-specific range: the same
  EXPECT_EQ(&typicalStrengths(motor, baseline(kHelical)), &motor.typical);
}

TEST(CandidateApplicability, PowerCheckTriesEachEffectAtItsWeakestRealisticStrength) {
  // The end of each realistic range nearer the value at which the effect vanishes (in the fit
  // coordinate): a hook 0.3-0.5 times as stiff (off at 1) is weakest at 0.5, not at 0.3
  const YAML::Node helical = baseline(kHelical);
  EXPECT_EQ(weakestTypicalStrength(candidateByName("hook_stiffness"), helical),
            std::vector<double>{0.5});
  EXPECT_EQ(weakestTypicalStrength(candidateByName("head_tilt_drag"), helical),
            std::vector<double>{2.5});
  int checked = 0;
  for (const char* config : {kGranular, kHelical})
    for (const Candidate& c : standardCandidates()) {
      const std::vector<double> weakest = weakestTypicalStrength(c, baseline(config));
      for (const TypicalStrength& t : typicalStrengths(c, baseline(config))) {
        const auto v = std::find_if(c.variables.begin(), c.variables.end(),
                                    [&](const FitParameter& p) { return p.name == t.variable; });
        ASSERT_NE(v, c.variables.end()) << c.name << ": " << t.variable;
        const size_t i = static_cast<size_t>(v - c.variables.begin());
        ASSERT_LT(i, weakest.size()) << c.name;
        ASSERT_LT(i, c.off.size()) << c.name;
        const double w = weakest[i], other = w == t.low ? t.high : t.low;
        EXPECT_TRUE(w == t.low || w == t.high) << c.name << " " << config;
        auto from_off = [&](double x) {
          return v->log_scale ? std::abs(std::log(x / c.off[i])) : std::abs(x - c.off[i]);
        };
        EXPECT_LE(from_off(w), from_off(other)) << c.name << " " << config << ": " << w;
        ++checked;
      }
    }
  EXPECT_GT(checked, 10);
}

TEST(CandidateApplicability, SingleFlagellumTrackSwimsTwiceAsFarAtTwiceTheRate) {
  const GeneratedCase g =
      generateCase(discoveryCaseByName("null_series"), baseline(kHelical), kHelical, 1);
  ASSERT_EQ(g.data.series.size(), 1u);
  const TimeSeries& s = g.data.series[0];
  ASSERT_GE(s.t.back(), 39.9);
  EXPECT_TRUE(s.overrides.empty());  // the baseline's robot
  // 20 s at 40 rpm, then 20 s at 80 rpm: Stokes swimming below the threshold is linear in the
  // rate, so the mean velocity over 10-20 s is half that over 30-40 s (each steady after 10 s).
  // The mean velocity is the least-squares slope of the positions, which averages out the head's
  // wobble once per turn. Within 6 %: the flagellum's tilt grows with the rate (4 % in the table
  // above) and each sample carries 0.2 mm of tracking noise per coordinate.
  const auto meanVelocity = [&](double from, double to) {
    std::vector<double> t;
    std::vector<double> p[3];
    for (size_t k = 0; k < s.t.size(); ++k) {
      if (s.t[k] < from - 1e-9 || s.t[k] > to + 1e-9) continue;
      t.push_back(s.t[k]);
      for (int a = 0; a < 3; ++a) p[a].push_back(s.position[k](a));
    }
    return Vec3(fitLine(t, p[0]).slope, fitLine(t, p[1]).slope, fitLine(t, p[2]).slope);
  };
  EXPECT_EQ(s.omega_cmd.front(), units::rpmToRadPerSec(40.0));
  EXPECT_EQ(s.omega_cmd.back(), units::rpmToRadPerSec(80.0));
  const double slow = meanVelocity(10.0, 20.0).norm(), fast = meanVelocity(30.0, 40.0).norm();
  EXPECT_GT(slow * 10.0, 10.0 * s.position_noise);  // over 2 mm in 10 s
  EXPECT_NEAR(fast / slow, 2.0, 0.12);
}

TEST(CandidateApplicability, SingleFlagellumTableIsOneRobotBelowItsThreshold) {
  const GeneratedCase g =
      generateCase(discoveryCaseByName("null_table"), baseline(kHelical), kHelical, 1);
  ASSERT_EQ(g.data.tables.size(), 1u);
  const SteadyStateTable& t = g.data.tables[0];
  ASSERT_EQ(t.rows.size(), 12u);
  // Straight below the threshold, Stokes swimming is linear in the motor rate: v / omega_T and
  // omega_h / omega_T are nearly the same at every rate. Noise-free they drift by under 4 % from
  // 20 to 90 rpm as the flagellum starts to tilt; each row may add 3 sigma of its noise.
  std::vector<double> v_ratio, h_ratio;
  for (const SteadyStateRow& row : t.rows) {
    EXPECT_TRUE(row.overrides.empty()) << row.id;  // the baseline's robot, no tail count
    EXPECT_LE(row.omega_T, units::rpmToRadPerSec(90.0) + 1e-9) << row.id;
    v_ratio.push_back(row.measured.at("v") / row.omega_T);
    h_ratio.push_back(std::abs(row.measured.at("omega_h")) / row.omega_T);
  }
  const auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
    return x[x.size() / 2];
  };
  // The table carries the flagellum's tilt (docs/model.md 8.4.4): below the threshold, under
  // the tilt that counts as buckled (the config's buckling_tilt_deg, 15 deg).
  ASSERT_EQ(t.noise.count("tilt"), 1u);
  EXPECT_NE(observablesOf(g.data) & kTilt, 0u);
  for (const SteadyStateRow& row : t.rows) {
    EXPECT_GT(row.measured.at("tilt"), -3.0 * t.noise.at("tilt")) << row.id;
    EXPECT_LT(row.measured.at("tilt"), units::degToRad(15.0)) << row.id;
  }
  const double v_mid = median(v_ratio), h_mid = median(h_ratio);
  EXPECT_GT(v_mid, 0.0);  // a pusher: forward
  for (size_t k = 0; k < t.rows.size(); ++k) {
    const double omega = t.rows[k].omega_T;
    EXPECT_LE(std::abs(v_ratio[k] - v_mid), 0.04 * v_mid + 3.0 * t.noise.at("v") / omega)
        << t.rows[k].id;
    EXPECT_LE(std::abs(h_ratio[k] - h_mid), 0.04 * h_mid + 3.0 * t.noise.at("omega_h") / omega)
        << t.rows[k].id;
  }
}

}  // namespace
}  // namespace identify
}  // namespace flagella
