// Which candidates and discovery cases apply to which robot: a granular yield or stick-slip acts
// only in the granular medium (resistive force theory in the config), a tail asymmetry only on a
// robot with two tails or more; a single-flagellum swimmer gets the table cases only, on its own
// plan of motor rates (docs/model.md 7.6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <vector>

#include "flagella_identify/candidates.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/model.h"
#include "flagella_sim/core/units.h"

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

TEST(CandidateApplicability, TailAsymmetryNeedsTwoTails) {
  const Candidate& c = candidateByName("fabrication_asymmetry");
  EXPECT_EQ(tailCountOf(baseline(kGranular)), 2);
  EXPECT_EQ(tailCountOf(baseline(kHelical)), 1);
  EXPECT_EQ(notApplicableReason(c, baseline(kGranular)), "");
  EXPECT_NE(notApplicableReason(c, baseline(kHelical)).find("1 tail"), std::string::npos);
}

TEST(CandidateApplicability, MotorAndMediumEffectsApplyToEveryRobot) {
  for (const std::string name : {"dc_motor", "viscosity_drift", "com_offset"})
    for (const char* robot : {kGranular, kHelical})
      EXPECT_EQ(notApplicableReason(candidateByName(name), baseline(robot)), "")
          << name << " on " << robot;
}

TEST(CandidateApplicability, EveryCaseAppliesToTheGranularRobot) {
  for (const DiscoveryCase& c : discoveryCases())
    EXPECT_EQ(caseNotApplicableReason(c, baseline(kGranular)), "") << c.name;
}

TEST(CandidateApplicability, TheSingleFlagellumRobotGetsTheTableCasesOfItsEffects) {
  std::set<std::string> applicable;
  for (const DiscoveryCase& c : discoveryCases())
    if (caseNotApplicableReason(c, baseline(kHelical)).empty()) applicable.insert(c.name);
  EXPECT_EQ(applicable, (std::set<std::string>{"null_table", "dc_motor", "viscosity_drift"}));
  EXPECT_THROW(generateCase(discoveryCaseByName("null_series"), baseline(kHelical), kHelical, 1),
               std::invalid_argument);
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
