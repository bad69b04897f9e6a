// Tests of SimSession with the shipped configs, against independent truths: the IMU and the
// snapshot describe the same head pose, the gyro's spin is theta_dot^0 and a slow swimmer's
// accelerometer reads +|g| upward, the output frame turns the sim's `up` into +z, motor commands
// follow the gate contract (reject, failsafe, initial behaviour), reset() is a fresh start, and
// solver failures follow the documented retry-then-halt strategy. Also RateSchedule.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/runtime/rate_schedule.h"
#include "flagella_sim/runtime/sim_session.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr char kDesign1[] = "granular_design1.yaml";
constexpr char kInterfaceRobot[] = "interface_robot.yaml";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What granular_design1.yaml says (checked against the loaded config below).
constexpr double kDesign1Rpm = 100.0;
constexpr double kDesign1Ramp = 0.5;  // [s]
constexpr double kDesign1Dt = 0.01;   // [s]

// Same double computations on both sides up to a rotation / normalisation.
constexpr double kExactTol = 1e-12;
// Gyro (finite difference of poses over one step) vs instantaneous theta_dot^0 in steady
// spinning: they differ by (d omega_h/dt) dt / omega_h, well below this.
constexpr double kSpinRelTol = 0.02;
// Slow swimmer: |head acceleration| << g, so the specific force is g to better than this.
constexpr double kGravityRelTol = 0.01;
// Head spin is steady (to < 1 %) after this long at 100 rpm with the 0.5 s ramp [s].
constexpr double kSpinUpTime = 2.0;
constexpr int kSteadySteps = 50;
constexpr int kSomeSteps = 50;

// A commanded motor speed inside the default +-200 rpm range [rad/s].
constexpr double kCommand = 5.0;
constexpr double kOtherCommand = -3.0;
constexpr double kTimeout = 0.2;  // [s]

// Overrides that make every Newton solve impossible: one update cannot reach 1e-10.
const std::vector<std::string> kImpossibleSolver{
    "solver.max_iterations=1", "solver.residual_tolerance=1e-10", "solver.max_subdivision_depth=2"};
// A marginal solver: 2 iterations and no subdivision follow the motor's 2 s soft start to steady
// 100 rpm, but neither an abrupt reversal nor an abrupt stop from there converges.
const std::vector<std::string> kMarginalSolver{
    "solver.max_iterations=2", "solver.max_subdivision_depth=0", "motor.ramp_time=2"};
constexpr int kMarginalWarmupSteps = 300;

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

SimulationConfig load(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return loadSimulationConfig(shippedConfig(name), overrides);
}

SessionOptions stoppedOptions(double timeout = 0.0) {
  SessionOptions o;
  o.initial_motor = "stopped";
  o.command_timeout = timeout;
  return o;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

double maxAbs(const Vec3& v) { return v.cwiseAbs().maxCoeff(); }

/// Quaternions describing the same rotation (q and -q) agree to tol.
double quaternionDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return std::min((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(),
                  (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff());
}

double maxNodeDifference(const RodSnapshot& a, const RodSnapshot& b) {
  if (a.nodes.size() != b.nodes.size()) return std::numeric_limits<double>::infinity();
  double d = 0.0;
  for (size_t i = 0; i < a.nodes.size(); ++i) d = std::max(d, maxAbs(a.nodes[i] - b.nodes[i]));
  return d;
}

void stepOrFail(SimSession& session, int steps) {
  for (int k = 0; k < steps; ++k) ASSERT_TRUE(session.step()) << "t = " << session.time();
}

// --------------------------------------------------------------------------------------------
// IMU and snapshot
// --------------------------------------------------------------------------------------------

TEST(SimSession, ImuOrientationIsTheSnapshotHeadOrientation) {
  for (const char* name : {kDesign1, kInterfaceRobot}) {
    SCOPED_TRACE(name);
    SimSession session(load(name), SessionOptions{});
    EXPECT_LT(
        quaternionDistance(session.measureImu().orientation, session.snapshot().head_orientation),
        kExactTol);
    for (int k = 0; k < kSomeSteps; ++k) {
      ASSERT_TRUE(session.step());
      const ImuSample imu = session.measureImu();
      const RodSnapshot snap = session.snapshot();
      ASSERT_LT(quaternionDistance(imu.orientation, snap.head_orientation), kExactTol)
          << "t = " << session.time();
      ASSERT_EQ(imu.time, snap.time);
    }
  }
}

TEST(SimSession, GyroReadsHeadSpinAndAccelerometerReadsGravityUp) {
  const SimulationConfig config = load(kDesign1);
  const double g = config.medium.gravity.norm();
  ASSERT_GT(g, 9.0);  // the shipped config has gravity (Medium default / -9.81 up)
  SimSession session(config, SessionOptions{});
  stepOrFail(session, static_cast<int>(std::lround(kSpinUpTime / config.dt)));
  for (int k = 0; k < kSteadySteps; ++k) {
    ASSERT_TRUE(session.step());
    const ImuSample imu = session.measureImu();
    const RodSnapshot snap = session.snapshot();
    ASSERT_GT(std::abs(snap.omega_h), 1.0) << "the head should be spinning";
    // Body z is the head axis t^0: its rate is the signed head spin theta_dot^0.
    EXPECT_NEAR(imu.angular_velocity.z(), snap.omega_h, kSpinRelTol * std::abs(snap.omega_h));
    EXPECT_NEAR(imu.linear_acceleration.norm(), g, kGravityRelTol * g);
    // In the output frame (z up) the specific force points up: REP-145, at rest-like motion.
    const Vec3 force_out = imu.orientation * imu.linear_acceleration;
    EXPECT_LT(maxAbs(force_out - g * Vec3::UnitZ()), kGravityRelTol * g) << force_out.transpose();
  }
}

// --------------------------------------------------------------------------------------------
// Output frame
// --------------------------------------------------------------------------------------------

TEST(SimSession, OutputFromSimulationFrameTurnsUpIntoZ) {
  for (const Vec3& up : {Vec3(Vec3::UnitZ()), Vec3(Vec3::UnitY()), Vec3(-Vec3::UnitZ()),
                         Vec3(Vec3::UnitX()), Vec3(1.0, -2.0, 3.0)}) {
    SCOPED_TRACE(up.transpose());
    const Eigen::Quaterniond r = outputFromSimulationFrame(up);
    EXPECT_NEAR(r.norm(), 1.0, kExactTol);
    EXPECT_LT(maxAbs(r * up.normalized() - Vec3::UnitZ()), kExactTol);
  }
}

TEST(SimSession, InterfaceRobotSnapshotIsRotatedIntoTheOutputFrame) {
  const SimulationConfig config = load(kInterfaceRobot);
  ASSERT_LT(maxAbs(config.medium.up - Vec3::UnitY()), kExactTol);  // interface_robot.yaml
  SimSession session(config, SessionOptions{});
  const Eigen::Quaterniond out = session.outputFrame();
  EXPECT_LT(maxAbs(out * config.medium.up - Vec3::UnitZ()), kExactTol);
  stepOrFail(session, kSomeSteps);
  const RodSnapshot snap = session.snapshot();
  const RodState& state = session.simulation().state();
  ASSERT_EQ(static_cast<int>(snap.nodes.size()), session.simulation().network().numNodes());
  for (size_t i = 0; i < snap.nodes.size(); ++i) {
    const Vec3 sim_x = nodePosition(state.q, static_cast<int>(i));
    ASSERT_LT(maxAbs(snap.nodes[i] - out * sim_x), kExactTol) << "node " << i;
    // Height above the sim's reference plane becomes z.
    ASSERT_NEAR(snap.nodes[i].z(), sim_x.dot(config.medium.up), kExactTol) << "node " << i;
  }
  EXPECT_LT(maxAbs(snap.head_position - out * session.simulation().sample().head_position),
            kExactTol);
  EXPECT_EQ(snap.time, session.time());
  EXPECT_TRUE(snap.allFinite());
}

// --------------------------------------------------------------------------------------------
// Motor commands
// --------------------------------------------------------------------------------------------

TEST(SimSession, StoppedMotorWaitsForACommand) {
  SimSession session(load(kDesign1), stoppedOptions());
  const RodSnapshot initial = session.snapshot();
  for (int k = 0; k < kSomeSteps; ++k) {
    ASSERT_TRUE(session.step());
    ASSERT_EQ(session.health().motor_applied, 0.0);
  }
  // Nothing drives the robot: it stays exactly at rest.
  EXPECT_EQ(session.snapshot().omega_h, 0.0);
  EXPECT_EQ(maxNodeDifference(session.snapshot(), initial), 0.0);

  EXPECT_EQ(session.commandMotor(kCommand), CommandVerdict::Accepted);
  for (int k = 0; k < kSomeSteps; ++k) {
    ASSERT_TRUE(session.step());
    ASSERT_EQ(session.health().motor_applied, kCommand);
    ASSERT_EQ(session.snapshot().omega_motor, kCommand);
  }
  EXPECT_GT(std::abs(session.snapshot().omega_h), 0.0);
  EXPECT_EQ(session.health().motor_accepted, 1);
}

TEST(SimSession, BadMotorCommandsAreRejectedAndTheLastValidOneKept) {
  const SessionOptions options = stoppedOptions();
  SimSession session(load(kDesign1), options);
  ASSERT_EQ(session.commandMotor(kCommand), CommandVerdict::Accepted);
  ASSERT_TRUE(session.step());
  EXPECT_EQ(session.commandMotor(kNaN), CommandVerdict::NotFinite);
  EXPECT_EQ(session.health().motor_rejected, 1);
  ASSERT_TRUE(session.step());
  EXPECT_EQ(session.health().motor_applied, kCommand);
  EXPECT_EQ(session.commandMotor(options.max_motor_speed * 1.01), CommandVerdict::OutOfRange);
  EXPECT_EQ(session.commandMotor(-options.max_motor_speed * 1.01), CommandVerdict::OutOfRange);
  EXPECT_EQ(session.health().motor_rejected, 3);
  EXPECT_EQ(session.health().motor_accepted, 1);
  ASSERT_TRUE(session.step());
  EXPECT_EQ(session.health().motor_applied, kCommand);
  EXPECT_TRUE(contains(session.health().last_rejection, "motor"))
      << session.health().last_rejection;
  EXPECT_EQ(session.health().level, HealthLevel::Ok);
  // The range bound itself is allowed.
  EXPECT_EQ(session.commandMotor(-options.max_motor_speed), CommandVerdict::Accepted);
}

TEST(SimSession, FailsafeStopsTheMotorAfterTheTimeoutAndANewCommandResumes) {
  SimSession session(load(kDesign1), stoppedOptions(kTimeout));
  const double dt = session.dt();
  ASSERT_EQ(session.commandMotor(kCommand), CommandVerdict::Accepted);
  const double command_time = session.time();
  bool tripped_seen = false;
  while (session.time() < command_time + kTimeout + 5.0 * dt) {
    const double step_start = session.time();
    // Garbage does not keep the motor alive.
    ASSERT_NE(session.commandMotor(kNaN), CommandVerdict::Accepted);
    ASSERT_TRUE(session.step());
    const SessionHealth h = session.health();
    // The motor set-point of a step is decided at its start ...
    if (step_start < command_time + kTimeout - 0.5 * dt) {
      ASSERT_EQ(h.motor_applied, kCommand) << "t = " << step_start;
    } else if (step_start > command_time + kTimeout + 0.5 * dt) {
      tripped_seen = true;
      ASSERT_EQ(h.motor_applied, 0.0) << "t = " << step_start;
      ASSERT_EQ(session.snapshot().omega_motor, 0.0);
    }
    // ... the reported failsafe state is that of the current time.
    if (session.time() < command_time + kTimeout - 0.5 * dt) {
      ASSERT_FALSE(h.failsafe_active) << "t = " << session.time();
      ASSERT_EQ(h.level, HealthLevel::Ok);
    } else if (session.time() > command_time + kTimeout + 0.5 * dt) {
      ASSERT_TRUE(h.failsafe_active) << "t = " << session.time();
      ASSERT_EQ(h.level, HealthLevel::Warn);
    }
  }
  ASSERT_TRUE(tripped_seen);
  EXPECT_EQ(session.commandMotor(kOtherCommand), CommandVerdict::Accepted);
  ASSERT_TRUE(session.step());
  EXPECT_EQ(session.health().motor_applied, kOtherCommand);
  EXPECT_FALSE(session.health().failsafe_active);
  EXPECT_EQ(session.health().level, HealthLevel::Ok);
}

TEST(SimSession, ConfigMotorFollowsTheConfigScheduleUntilTheFirstCommand) {
  const SimulationConfig config = load(kDesign1);
  // The yaml's motor: constant 100 rpm with a 0.5 s linear soft start.
  ASSERT_EQ(config.motor.mode, "constant");
  ASSERT_NEAR(config.motor.omega, units::rpmToRadPerSec(kDesign1Rpm), kExactTol);
  ASSERT_EQ(config.motor.ramp_time, kDesign1Ramp);
  ASSERT_EQ(config.dt, kDesign1Dt);
  const double omega = units::rpmToRadPerSec(kDesign1Rpm);
  SimSession session(config, SessionOptions{});
  EXPECT_EQ(session.health().motor_applied, 0.0);
  // The step to t uses omega_T(t) = omega min(1, t / ramp) (implicit in the motor twist).
  const int steps = static_cast<int>(std::lround(1.5 * kDesign1Ramp / kDesign1Dt));
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(session.step());
    const double expected = omega * std::min(1.0, session.time() / kDesign1Ramp);
    ASSERT_NEAR(session.health().motor_applied, expected, kExactTol * omega) << session.time();
  }
  // A rejected command does not replace the schedule; a valid one does.
  EXPECT_EQ(session.commandMotor(kNaN), CommandVerdict::NotFinite);
  ASSERT_TRUE(session.step());
  EXPECT_NEAR(session.health().motor_applied, omega, kExactTol * omega);
  EXPECT_EQ(session.commandMotor(kCommand), CommandVerdict::Accepted);
  ASSERT_TRUE(session.step());
  EXPECT_EQ(session.health().motor_applied, kCommand);
}

TEST(SimSession, SliderCommandsAreGatedAndHeld) {
  const SessionOptions options;
  SimSession session(load(kDesign1), options);
  EXPECT_EQ(session.health().slider_position, 0.0);  // 0 lies inside [slider_min, slider_max]
  EXPECT_EQ(session.commandSlider(0.5 * options.slider_max), CommandVerdict::Accepted);
  EXPECT_EQ(session.commandSlider(2.0 * options.slider_max), CommandVerdict::OutOfRange);
  EXPECT_EQ(session.commandSlider(kNaN), CommandVerdict::NotFinite);
  stepOrFail(session, kSomeSteps);  // no failsafe on the slider: it stays where it was put
  const SessionHealth h = session.health();
  EXPECT_EQ(h.slider_position, 0.5 * options.slider_max);
  EXPECT_EQ(h.slider_accepted, 1);
  EXPECT_EQ(h.slider_rejected, 2);
  EXPECT_EQ(h.motor_rejected, 0);
}

TEST(SimSession, SliderCommandsMoveAConfiguredSliderIntoItsStop) {
  // helical robot with a slider (travel +-8 mm) and the session's wider command range +-20 mm:
  // a command past the travel is accepted by the gate and ends against the hard stop (reported).
  SimulationConfig config = loadSimulationConfig(
      shippedConfig("helical_robot.yaml"),
      {"motor.omega_rpm=0", "slider.travel_min=-0.008", "slider.travel_max=0.008"});
  SessionOptions options;
  SimSession session(config, options);
  EXPECT_EQ(session.health().slider_position, 0.0);
  EXPECT_EQ(session.commandSlider(0.015), CommandVerdict::Accepted);
  const double v_max = config.slider.maxSpeed();
  stepOrFail(session, 100);  // 1 s at 2.5 mm/s: on its way
  SessionHealth h = session.health();
  EXPECT_GT(h.slider_position, 0.5 * v_max);
  EXPECT_LE(h.slider_position, 1.0 * v_max);
  EXPECT_FALSE(h.slider_at_stop);
  stepOrFail(session, 300);  // 4 s in all: 8 mm reached after 3.3 s
  h = session.health();
  EXPECT_EQ(h.slider_position, 0.008);
  EXPECT_TRUE(h.slider_at_stop);
  EXPECT_EQ(session.simulation().slider()->state().stop_hits, 1);
}

TEST(SimSession, AccelerometerGivesTheHeadTiltTheCoupleProduces) {
  // helical robot, motor off, COM 2 mm behind the COV: the couple pitches the head; the
  // noise-free accelerometer's elevation follows the true axis within its 3.9 mg resolution
  // and the slow head motion, once the start from rest is over.
  SimulationConfig config = loadSimulationConfig(
      shippedConfig("helical_robot.yaml"), {"motor.omega_rpm=0", "effects.com_offset.offset=2e-3"});
  SessionOptions options;
  options.accelerometer.noise_std = 0.0;
  SimSession session(config, options);
  double largest = 0.0;
  for (int k = 0; k < 200; ++k) {
    stepOrFail(session, 1);
    const AccelerometerReading& r = session.measureAccelerometer();
    const Vec3 axis = session.simulation().sample().head_axis;
    const double truth = std::asin(axis.y() / axis.norm());
    if (k < 10) continue;  // the start from rest accelerates the head at up to 0.15 g
    EXPECT_NEAR(headElevationFromAcceleration(r.acceleration), truth, 0.5 * M_PI / 180.0)
        << "t = " << session.time() << ", |a| = " << r.acceleration.norm();
    largest = std::max(largest, std::abs(truth));
  }
  EXPECT_GT(largest, 10.0 * M_PI / 180.0);  // it did pitch
  session.reset();
  EXPECT_EQ(session.measureAccelerometer().time, 0.0);
}

// --------------------------------------------------------------------------------------------
// Reset
// --------------------------------------------------------------------------------------------

TEST(SimSession, ResetIsAFreshStart) {
  const SimulationConfig config = load(kDesign1);
  SimSession session(config, SessionOptions{});
  const RodSnapshot initial = session.snapshot();
  stepOrFail(session, kSomeSteps);
  ASSERT_EQ(session.commandMotor(kCommand), CommandVerdict::Accepted);
  stepOrFail(session, kSomeSteps);
  ASSERT_GT(maxNodeDifference(session.snapshot(), initial), 0.0);

  session.reset();
  EXPECT_EQ(session.time(), 0.0);
  EXPECT_FALSE(session.halted());
  EXPECT_EQ(maxNodeDifference(session.snapshot(), initial), 0.0);
  EXPECT_EQ(session.snapshot().omega_h, 0.0);
  EXPECT_EQ(session.health().motor_applied, 0.0);
  EXPECT_EQ(session.measureImu().angular_velocity, Vec3::Zero());

  // The command is forgotten: the run from here is exactly that of a new session.
  SimSession fresh(config, SessionOptions{});
  for (int k = 0; k < kSomeSteps; ++k) {
    ASSERT_TRUE(session.step());
    ASSERT_TRUE(fresh.step());
    ASSERT_EQ(session.health().motor_applied, fresh.health().motor_applied) << k;
    ASSERT_EQ(maxNodeDifference(session.snapshot(), fresh.snapshot()), 0.0) << k;
  }
}

// --------------------------------------------------------------------------------------------
// Solver failures
// --------------------------------------------------------------------------------------------

TEST(SimSession, FailedStepIsRetriedWithTheMotorStopped) {
  // From rest the motor-stopped retry has nothing to solve, so it succeeds: a warning.
  SimSession session(load(kDesign1, kImpossibleSolver), SessionOptions{});
  const RodSnapshot initial = session.snapshot();
  EXPECT_TRUE(session.step());
  const SessionHealth h = session.health();
  EXPECT_FALSE(h.halted);
  EXPECT_EQ(h.solver_failures, 1);
  EXPECT_EQ(h.level, HealthLevel::Warn);
  EXPECT_EQ(h.motor_applied, 0.0);
  EXPECT_FALSE(h.last_solver_failure.empty());
  EXPECT_NEAR(session.time(), session.dt(), kExactTol);
  EXPECT_EQ(session.snapshot().omega_motor, 0.0);
  EXPECT_EQ(maxNodeDifference(session.snapshot(), initial), 0.0);  // nothing drove it
}

TEST(SimSession, HaltsWhenTheStoppedMotorRetryFailsToo) {
  const SimulationConfig config = load(kDesign1, kMarginalSolver);
  const double omega = config.motor.omega;
  SimSession session(config, SessionOptions{});
  stepOrFail(session, kMarginalWarmupSteps);
  ASSERT_EQ(session.health().solver_failures, 0);
  const RodSnapshot before = session.snapshot();
  const double time_before = session.time();

  ASSERT_EQ(session.commandMotor(-omega), CommandVerdict::Accepted);  // abrupt reversal
  EXPECT_FALSE(session.step());
  SessionHealth h = session.health();
  EXPECT_TRUE(h.halted);
  EXPECT_TRUE(session.halted());
  EXPECT_EQ(h.level, HealthLevel::Error);
  EXPECT_GE(h.solver_failures, 1);
  EXPECT_TRUE(contains(h.message, "halted")) << h.message;
  EXPECT_FALSE(h.last_solver_failure.empty());

  // The state is the last good step.
  const RodSnapshot after = session.snapshot();
  EXPECT_TRUE(after.allFinite());
  EXPECT_EQ(after.time, time_before);
  EXPECT_EQ(maxNodeDifference(after, before), 0.0);
  EXPECT_EQ(after.omega_h, before.omega_h);
  EXPECT_EQ(session.health().motor_applied, after.omega_motor);  // what the last good step used
  EXPECT_TRUE(session.measureImu().angular_velocity.allFinite());

  // Halted: nothing moves until reset, whatever is commanded.
  EXPECT_EQ(session.commandMotor(omega), CommandVerdict::Accepted);
  for (int k = 0; k < 3; ++k) {
    EXPECT_FALSE(session.step());
    EXPECT_EQ(session.time(), time_before);
  }
  EXPECT_EQ(maxNodeDifference(session.snapshot(), before), 0.0);
  EXPECT_EQ(session.health().level, HealthLevel::Error);

  session.reset();
  EXPECT_EQ(session.time(), 0.0);
  EXPECT_FALSE(session.halted());
  EXPECT_FALSE(session.health().halted);
  // A reset is a fresh start: nothing of the failed run is reported any more.
  EXPECT_EQ(session.health().level, HealthLevel::Ok);
  EXPECT_EQ(session.health().solver_failures, 0);
  EXPECT_EQ(session.health().motor_accepted, 0);
  EXPECT_TRUE(session.health().last_solver_failure.empty());
  EXPECT_TRUE(session.step());  // the soft start converges again
}

// --------------------------------------------------------------------------------------------
// Option validation
// --------------------------------------------------------------------------------------------

void expectConfigError(const SessionOptions& o, const std::string& field) {
  SCOPED_TRACE(field);
  const std::string message = testing::errorMessageOf<ConfigError>([&] { o.validate(); });
  EXPECT_TRUE(contains(message, field)) << message;
}

TEST(SessionOptions, RejectsUnusableValuesNamingTheField) {
  EXPECT_NO_THROW(SessionOptions{}.validate());
  EXPECT_NO_THROW(stoppedOptions().validate());
  for (double bad : {0.0, -1.0, kNaN}) {
    SessionOptions o;
    o.max_motor_speed = bad;
    expectConfigError(o, "max_motor_speed");
  }
  for (double bad : {-0.1, kNaN}) {
    SessionOptions o;
    o.command_timeout = bad;
    expectConfigError(o, "command_timeout");
  }
  SessionOptions o;
  o.initial_motor = "running";
  expectConfigError(o, "initial_motor");
  o = SessionOptions{};
  o.slider_min = 0.01;
  o.slider_max = -0.01;
  expectConfigError(o, "slider_max");
  o = SessionOptions{};
  o.imu.gyro_noise_std = -1.0;
  expectConfigError(o, "imu.gyro_noise_std");
  // The session refuses them too.
  o = SessionOptions{};
  o.command_timeout = -1.0;
  EXPECT_THROW(SimSession(load(kDesign1), o), ConfigError);
}

// --------------------------------------------------------------------------------------------
// RateSchedule
// --------------------------------------------------------------------------------------------

constexpr double kRateHz = 10.0;
constexpr double kScheduleDuration = 10.0;  // [s]
// Gaps are sums of ten 0.01 steps: round-off only.
constexpr double kGapTol = 1e-9;

std::vector<double> firingTimes(RateSchedule& schedule, double dt, double duration) {
  std::vector<double> fired;
  double t = 0.0;
  const long steps = std::lround(duration / dt);
  for (long k = 0; k < steps; ++k) {
    t += dt;  // accumulated like the simulation's clock
    if (schedule.due(t)) fired.push_back(t);
  }
  return fired;
}

TEST(RateSchedule, FiresAtTheRateEvenly) {
  RateSchedule schedule(kRateHz);
  EXPECT_DOUBLE_EQ(schedule.period(), 1.0 / kRateHz);
  const std::vector<double> fired = firingTimes(schedule, kDesign1Dt, kScheduleDuration);
  const double expected = kRateHz * kScheduleDuration;
  EXPECT_LE(std::abs(static_cast<double>(fired.size()) - expected), 1.0) << fired.size();
  for (size_t i = 1; i < fired.size(); ++i)
    ASSERT_NEAR(fired[i] - fired[i - 1], 1.0 / kRateHz, kGapTol) << "firing " << i;
}

TEST(RateSchedule, DoesNotDriftWhenThePeriodIsNotAMultipleOfTheStep) {
  // dt = 0.03 s, period 0.1 s: firing k happens at the first tick at or after t0 + k period.
  constexpr double kOddDt = 0.03;
  RateSchedule schedule(kRateHz);
  const std::vector<double> fired = firingTimes(schedule, kOddDt, kScheduleDuration);
  ASSERT_FALSE(fired.empty());
  const double period = 1.0 / kRateHz;
  const double t0 = fired.front();
  EXPECT_LE(std::abs(static_cast<double>(fired.size()) - kRateHz * kScheduleDuration), 1.0);
  for (size_t k = 1; k < fired.size(); ++k) {
    const double deadline = t0 + k * period;
    ASSERT_GE(fired[k], deadline - kGapTol) << "firing " << k;
    ASSERT_LT(fired[k], deadline + kOddDt - kGapTol) << "firing " << k;
  }
}

TEST(RateSchedule, ZeroRateFiresEveryTimeAndRestartReanchors) {
  RateSchedule every(0.0);
  const std::vector<double> fired = firingTimes(every, kDesign1Dt, 1.0);
  EXPECT_EQ(fired.size(), 100u);
  RateSchedule schedule(kRateHz);
  EXPECT_TRUE(schedule.due(5.0));
  EXPECT_FALSE(schedule.due(5.05));
  schedule.restart();
  EXPECT_TRUE(schedule.due(5.05));  // anchored anew
  EXPECT_FALSE(schedule.due(5.1));
  EXPECT_TRUE(schedule.due(5.15));
}

}  // namespace
}  // namespace flagella
