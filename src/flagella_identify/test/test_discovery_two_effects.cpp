// Two hidden effects in one steady-state table (granular yield and a DC-motor torque-speed
// curve): the motor's speed deficit dominates the discrepancy, so the yield threshold on its own
// does not even lower the held-out error; the tool must still name both, with a held-out gain
// of at least 50 %.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoveryTwoEffects, GranularYieldAndDcMotor) { expectFound("granular_yield+dc_motor", 2); }

}  // namespace testing
}  // namespace identify
}  // namespace flagella
