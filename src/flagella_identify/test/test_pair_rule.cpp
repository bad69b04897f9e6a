// The pair rule (docs/model.md 7.6): a pair is named only when its first effect, fitted again
// alone from the pair's optimum, cannot do as well. A single effect's fit stopped short of its
// optimum (an iteration cap) leaves a residual that a second effect absorbs; without the rule
// the verdict rests on pairs (measured: "cannot tell between dc_motor + granular_yield and
// dc_motor + viscosity_drift"), with it the hidden effect alone is named.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {
namespace {

IdentifyResult runCapped(const std::string& name, int seed, int cap, bool pair_rule) {
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  const GeneratedCase generated =
      generateCase(discoveryCaseByName(name), baseline, baselinePath(), seed);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.evaluator.jobs = 1;
  options.single_fit_max_iterations = cap;
  options.pair_rule = pair_rule;
  Identification identification(generated.data, baseline, baselinePath(), options);
  const IdentifyResult result = identification.run();
  std::cout << generated.description << "\n  -> " << verdictText(result.verdict) << ": "
            << result.summary << std::endl;
  return result;
}

TEST(PairRule, ASingleFitStoppedShortDoesNotMakeAPair) {
  const std::string name = "dc_motor";
  const IdentifyResult without = runCapped(name, 2, 1, false);
  const IdentifyResult with = runCapped(name, 2, 1, true);
  ASSERT_TRUE(without.chosen.has_value()) << without.summary;
  EXPECT_EQ(without.chosen->effects.size(), 2u) << without.summary;
  EXPECT_NE(without.named, discoveryCaseByName(name).hidden) << without.summary;
  EXPECT_EQ(with.verdict, Verdict::kNamedCause) << with.summary;
  EXPECT_EQ(with.named, discoveryCaseByName(name).hidden) << with.summary;
  EXPECT_NE(with.pair_check.find("not named"), std::string::npos) << with.pair_check;
}

}  // namespace
}  // namespace testing
}  // namespace identify
}  // namespace flagella
