// The strong lateral-force cases for the other tail counts (test_discovery_strong has 4 tails,
// with a competing candidate): C_yr drawn from 40x the typical range, so that the design-1 robot
// with 2, 3 or 5 tails circles on a radius under a body length. With the lateral force as the
// only candidate (flagella_discovery_bench --cases strong_lateral_{2..5}_tails runs the whole
// list), it must be named and its coefficient recovered, whatever the baseline calibration did
// on the circles (a baseline off its map must be reported, docs/model.md 7.6).
#include "support/discovery_check.h"

namespace flagella::identify::testing {
namespace {

class StrongLateralForce : public ::testing::TestWithParam<int> {};

TEST_P(StrongLateralForce, NamedWithItsCoefficient) {
  const int tails = GetParam();
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  const GeneratedCase generated =
      generateCase(discoveryCaseByName("strong_lateral_" + std::to_string(tails) + "_tails"),
                   baseline, baselinePath(), 1);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.candidates = {"interface_lateral_force"};
  options.evaluator.jobs = 1;
  Identification identification(generated.data, baseline, baselinePath(), options);
  const IdentifyResult r = identification.run();
  std::cout << generated.description << "\n  -> " << verdictText(r.verdict) << ": " << r.summary
            << std::endl;
  // a baseline off its map is never silent
  EXPECT_EQ(
      r.summary.find("Caution: the calibrated baseline ended off its map") != std::string::npos,
      !r.baseline.warnings.empty())
      << r.summary;
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"interface_lateral_force"}) << r.summary;
  ASSERT_TRUE(r.chosen);
  EXPECT_GE(r.gain, 0.5);
  const double truth = generated.truth.at("interface_lateral_force.C_yr");
  bool found = false;
  for (const FitParameter& p : r.chosen->parameters)
    if (p.name == "interface_lateral_force.C_yr") {
      found = true;
      EXPECT_NEAR(p.value, truth, std::max(3.0 * p.uncertainty, 0.2 * std::abs(truth)));
    }
  EXPECT_TRUE(found);
}

INSTANTIATE_TEST_SUITE_P(TwoThreeFiveTails, StrongLateralForce, ::testing::Values(2, 3, 5));

}  // namespace
}  // namespace flagella::identify::testing
