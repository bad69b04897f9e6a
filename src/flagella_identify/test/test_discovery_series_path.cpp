// Hidden effects in time series (the same robot, plan and noise as test_discovery_series) that
// bend the path sideways: the lateral head force near an interface (circling, reversing with
// the sign of rotation) and a fabrication asymmetry (one tail shorter or stiffer: a wobble at
// the tail rate and a curved path).
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoverySeriesPath, InterfaceLateralForceCircling) {
  expectFound("interface_lateral_force", 2);
}
TEST(DiscoverySeriesPath, FabricationAsymmetry) { expectFound("fabrication_asymmetry", 2); }

}  // namespace testing
}  // namespace identify
}  // namespace flagella
