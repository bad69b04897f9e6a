// Null data sets (the truth is the baseline robot with other parameter values): over ten of
// them, five tables and five time series, a cause may be named at most once.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoveryNull, AtMostOneCauseNamedOverTenNullDataSets) {
  int named = 0, runs = 0;
  for (const char* name : {"null_table", "null_series"})
    for (int seed = 11; seed <= 15; ++seed) {
      const CaseOutcome o = runCase(name, seed);
      ++runs;
      if (!o.result.named.empty()) ++named;
      // Whatever the verdict, a calibrated baseline must describe its own model family.
      EXPECT_NE(o.result.verdict, Verdict::kUnexplained) << o.generated.description;
    }
  EXPECT_EQ(runs, 10);
  EXPECT_LE(named, 1);
}

}  // namespace testing
}  // namespace identify
}  // namespace flagella
