// Granular stick-slip hidden in a time series (the same robot, plan and noise as
// test_discovery_series): the head stops where the jammed grains come to hold its thrust, and
// advances in sawtooth cycles where the thrust exceeds the release force. In its own binary so
// that ctest runs it beside the other discovery suites.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoverySeriesJamming, GranularJammingStickSlip) { expectFound("granular_jamming", 2); }

}  // namespace testing
}  // namespace identify
}  // namespace flagella
