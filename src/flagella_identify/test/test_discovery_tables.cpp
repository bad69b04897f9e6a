// Hidden effects in steady-state tables (design-1 granular robot, 14 experiments, noise of
// video tracking and turn counting): the tool must name the hidden effect, with a held-out
// gain of at least 50 %.
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {

TEST(DiscoveryTables, GranularYieldThreshold) { expectFound("granular_yield", 2); }
TEST(DiscoveryTables, DcMotorTorqueSpeedCurve) { expectFound("dc_motor", 2); }
TEST(DiscoveryTables, ViscosityDriftWithTemperature) { expectFound("viscosity_drift", 2); }

}  // namespace testing
}  // namespace identify
}  // namespace flagella
