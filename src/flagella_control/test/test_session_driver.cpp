// The calibration runs' session driver (session_driver.h) on a coarse source robot with the
// config's 1 s soft start: the rate it reports as applied is the rate the simulator's motor
// applied (its own record, read from the snapshot), so the shaft angle the calibration
// integrates is the motor's. It falls short of the commanded integral by the closed-form soft
// start deficit omega (ramp - dt) / 2; before this was checked, the calibration integrated the
// commanded rate and its buckle phase law was 2.1 rad off for a controller, whose commands the
// simulator applies without a soft start (docs/model.md 7.4).
#include <gtest/gtest.h>

#include <cmath>

#include "flagella_control/session_driver.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace fc = flagella::control;

TEST(SessionDriver, ReportsTheRateTheMotorAppliedThroughTheSoftStart) {
  const flagella::SimulationConfig config = flagella::loadSimulationConfig(
      std::string(FLAGELLA_CONFIG_DIR) + "/helical_steering_source.yaml",
      {"robot.edge_length=0.015"});
  const double ramp = config.motor.ramp_time;
  ASSERT_GT(ramp, 0.0);
  const double omega = 4.2;  // [rad/s], the source robot's cruise
  fc::SessionDriver driver(config, omega, "soft start");
  const double dt = driver.dt();
  const long steps = std::lround(2.0 * ramp / dt);
  double reported = 0.0, motor = 0.0;
  for (long k = 0; k < steps; ++k) {
    reported += driver.step(omega) * dt;
    motor += driver.session().snapshot().omega_motor * dt;
  }
  EXPECT_NEAR(reported, motor, 1e-12 * steps * omega * dt);
  const double commanded = steps * omega * dt;
  EXPECT_NEAR(commanded - reported, omega * (ramp - dt) / 2.0, 1e-9);
  // After the ramp the full rate is applied.
  EXPECT_DOUBLE_EQ(driver.step(omega), omega);
}
