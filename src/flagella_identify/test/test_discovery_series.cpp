// Hidden effects in time series (design-1 granular robot, 90 s with a command staircase
// 120, 240, -180 rpm; video tracking 0.2 mm, IMU 0.01 rad, turn counting 0.1 turn) that show in
// the head's pitch, and an effect outside the candidate list (a motor-speed ripple)
// that must be reported as an unexplained residual, never as a wrong name.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoverySeries, CentreOfMassOffsetPitchDrift) { expectFound("com_offset", 2); }

TEST(DiscoverySeries, EffectOutsideTheCandidateListIsAnUnexplainedResidual) {
  const CaseOutcome o = runCase("unknown_ripple", 2);
  EXPECT_EQ(o.result.verdict, Verdict::kUnexplained) << o.result.summary;
  EXPECT_TRUE(o.result.named.empty()) << o.result.summary;
  EXPECT_FALSE(o.result.baseline_diagnosis.signatures.empty())
      << "an unexplained residual must come with its signature";
}

}  // namespace testing
}  // namespace identify
}  // namespace flagella
