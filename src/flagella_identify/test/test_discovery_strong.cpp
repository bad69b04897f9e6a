// A lateral head force strong enough that the robot circles on a radius well under a body
// length (the discovery case strong_lateral_4_tails: C_yr drawn from 40x the typical range, a
// 4-tailed design-1 robot). Fitted on positions, the straight-swimming baseline runs off its map
// (the least-squares answer to a circle is not to move), and a candidate fitted from there
// inherits it (docs/model.md 7.6). The baseline must be reported off its map, the candidates
// fitted again by continuation, and the lateral force named. Two candidates keep the test short
// (com_offset, which a misfitted lateral force pairs with, costs minutes by continuation);
// flagella_discovery_bench --cases strong_lateral_{2..5}_tails runs the whole list.
#include "support/discovery_check.h"

namespace flagella::identify::testing {
namespace {

TEST(DiscoveryStrong, CirclingRobotLateralForceNamedThroughContinuation) {
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  const GeneratedCase generated =
      generateCase(discoveryCaseByName("strong_lateral_4_tails"), baseline, baselinePath(), 1);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.candidates = {"interface_lateral_force", "granular_yield"};
  options.evaluator.jobs = 1;
  Identification identification(generated.data, baseline, baselinePath(), options);
  const IdentifyResult r = identification.run();
  std::cout << generated.description << "\n  -> " << verdictText(r.verdict) << ": " << r.summary
            << std::endl;
  EXPECT_FALSE(r.baseline.warnings.empty()) << "the baseline was expected off its map";
  EXPECT_NE(r.summary.find("Caution: the calibrated baseline ended off its map"),
            std::string::npos);
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"interface_lateral_force"}) << r.summary;
  ASSERT_TRUE(r.chosen);
  EXPECT_TRUE(r.chosen->continuation);
  EXPECT_GE(r.gain, 0.5);
  // the fitted coefficient within 3 sigma (and 20 %) of the truth
  const double truth = generated.truth.at("interface_lateral_force.C_yr");
  for (const FitParameter& p : r.chosen->parameters)
    if (p.name == "interface_lateral_force.C_yr") {
      EXPECT_NEAR(p.value, truth, std::max(3.0 * p.uncertainty, 0.2 * std::abs(truth)));
    }
}

}  // namespace
}  // namespace flagella::identify::testing
