// The headless harness: the core simulator and a controller core exchange every message over
// LCM (memq://, in-process, no ROS master), commands arrive on the step after they are computed,
// bad commands are rejected by the simulator's gate and the failsafe stops the motor, the
// physics is the same as driving the motor schedule directly in the core, and camera fixes arrive
// at their rate (none in the dropout window) and reach the controller once each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/lcm_harness.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace units = flagella::units;

namespace flagella::control {
namespace {

const std::string kConfig = std::string(FLAGELLA_CONFIG_DIR) + "/interface_path_planning.yaml";
constexpr double kOmega = units::rpmToRadPerSec(43.27);  // [rad/s], the config's omega_H
constexpr double kHalfPeriod = 5.0;                      // [s]
constexpr double kDuration = 20.0;                       // [s]: two full switching periods
constexpr double kImuRate = 100.0, kStateRate = 20.0;    // [Hz]
// Switching instants differ by at most one step (0.01 s of each 5 s half): the head path may
// differ by a fraction of a percent of the distance travelled.
constexpr double kSamePathTol = 0.01;

flagella::SimulationConfig config() {
  return flagella::loadSimulationConfig(kConfig, {"motor.ramp_time=0"});
}

flagella::SessionOptions sessionOptions() {
  flagella::SessionOptions o;
  o.initial_motor = "stopped";
  o.imu.rate = kImuRate;
  o.command_timeout = 0.5;
  return o;
}

HarnessOptions harnessOptions() {
  HarnessOptions o;
  o.lcm_url = "memq://";
  o.state_rate = kStateRate;
  return o;
}

double schedule(double t) {
  return std::fmod(t, 2.0 * kHalfPeriod) < kHalfPeriod ? kOmega : -kOmega;
}

TEST(LcmHarness, EveryMessageArrivesAndCommandsApplyOnTheNextStep) {
  flagella::SimSession session(config(), sessionOptions());
  PeriodicSwitchController controller(kOmega, kHalfPeriod, kHalfPeriod);
  LcmHarness harness(session, controller, harnessOptions());
  long checked_steps = 0;
  const HarnessReport report = harness.run(kDuration, [&] {
    // The step just taken started at t - dt and used the command computed from the IMU
    // sample at that instant; the controller saw that time as the message's nanosecond stamp.
    const double step_start = session.time() - session.dt();
    const double stamp = std::round(step_start * 1e9) / 1e9;
    ASSERT_EQ(session.health().motor_applied, schedule(stamp)) << "t = " << step_start;
    ++checked_steps;
  });
  EXPECT_FALSE(report.halted);
  const LcmChannels ch = LcmChannels::withPrefix("FLAGELLA_");
  const long imu_samples = std::lround(kDuration * kImuRate) + 1;  // t = 0 and every period
  EXPECT_EQ(report.published.at(ch.imu), imu_samples);
  EXPECT_EQ(report.published.at(ch.rod_state), std::lround(kDuration * kStateRate) + 1);
  EXPECT_EQ(report.received.at(ch.imu), imu_samples);
  EXPECT_EQ(report.published.at(ch.motor_command), imu_samples);
  EXPECT_EQ(report.received.at(ch.motor_command), imu_samples);
  EXPECT_EQ(session.health().motor_rejected, 0);
  EXPECT_EQ(checked_steps, std::lround(kDuration / session.dt()));
}

TEST(LcmHarness, SamePhysicsAsTheMotorScheduleDrivenInTheCore) {
  flagella::SimSession session(config(), sessionOptions());
  PeriodicSwitchController controller(kOmega, kHalfPeriod, kHalfPeriod);
  LcmHarness harness(session, controller, harnessOptions());
  const flagella::Vec3 start = session.snapshot().head_position;
  harness.run(kDuration);
  const flagella::Vec3 via_lcm = session.snapshot().head_position - start;

  flagella::Simulation direct(config());  // the config's own binary +/-omega schedule
  const flagella::Vec3 direct_start = direct.sample().head_position;
  for (long k = 0; k < std::lround(kDuration / direct.config().dt); ++k) direct.step();
  const flagella::Vec3 direct_moved =
      session.outputFrame() * (direct.sample().head_position - direct_start);

  ASSERT_GT(direct_moved.norm(), 1e-3) << "the robot must travel for this to mean anything";
  EXPECT_LT((via_lcm - direct_moved).norm(), kSamePathTol * direct_moved.norm())
      << "via LCM " << via_lcm.transpose() << ", direct " << direct_moved.transpose();
}

/// Sends valid commands until t_fault, then NaN: a controller firmware gone wrong.
class FaultyController : public ControllerCore {
 public:
  explicit FaultyController(double t_fault) : t_fault_(t_fault) {}
  ControllerOutputs step(const ControllerInputs& in) override {
    ControllerOutputs out;
    out.motor_command = in.time < t_fault_ ? kOmega : std::numeric_limits<double>::quiet_NaN();
    out.mode = ControllerMode::Running;
    return out;
  }
  void reset() override {}
  const char* name() const override { return "faulty"; }

 private:
  double t_fault_;
};

TEST(LcmHarness, BadCommandsAreRejectedAndTheFailsafeStopsTheMotor) {
  constexpr double kFault = 1.0;  // [s]
  flagella::SessionOptions options = sessionOptions();
  flagella::SimSession session(config(), options);
  FaultyController controller(kFault);
  LcmHarness harness(session, controller, harnessOptions());
  harness.run(kFault + 0.5 * options.command_timeout);
  EXPECT_GT(session.health().motor_rejected, 0);
  EXPECT_EQ(session.health().motor_applied, kOmega) << "last valid command kept";
  harness.run(options.command_timeout);
  EXPECT_EQ(session.health().motor_applied, 0.0) << "failsafe after the timeout";
  EXPECT_TRUE(session.health().failsafe_active);
  EXPECT_TRUE(session.snapshot().allFinite());
}

/// Records the steps that carried a camera fix; commands a constant rate.
class FixRecordingController : public ControllerCore {
 public:
  struct Fix {
    double time;
    double x, y;
  };
  explicit FixRecordingController(std::size_t capacity) { fixes_.reserve(capacity); }
  ControllerOutputs step(const ControllerInputs& in) override {
    ++steps_;
    if (in.position_valid && fixes_.size() < fixes_.capacity())  // never allocates in step()
      fixes_.push_back({in.time, in.position[0], in.position[1]});
    ControllerOutputs out;
    out.motor_command = kOmega;
    out.mode = ControllerMode::Running;
    return out;
  }
  void reset() override {}
  const char* name() const override { return "fix_recorder"; }
  const std::vector<Fix>& fixes() const { return fixes_; }
  long steps() const { return steps_; }

 private:
  std::vector<Fix> fixes_;
  long steps_ = 0;
};

TEST(LcmHarness, CameraFixesArriveAtTheirRateAndReachTheControllerOnce) {
  constexpr double kCameraRate = 2.0;                       // [Hz]
  constexpr double kDropoutStart = 2.0, kDropoutEnd = 3.0;  // [s]
  constexpr double kRun = 5.0;                              // [s]
  // Fixes due every 0.5 s from t = 0; the two due inside [2, 3) are withheld.
  const std::vector<double> expected_times = {0.0, 0.5, 1.0, 1.5, 3.0, 3.5, 4.0, 4.5, 5.0};
  // Nanosecond stamps of summed steps.
  constexpr double kStampTol = 1e-8;
  // The same head position through a quaternion and through its matrix: round-off only.
  constexpr double kPositionTol = 1e-12;

  flagella::SessionOptions options = sessionOptions();
  options.camera.rate = kCameraRate;
  options.camera.dropout_start = kDropoutStart;
  options.camera.dropout_end = kDropoutEnd;
  flagella::SimSession session(config(), options);
  FixRecordingController controller(100);
  LcmHarness harness(session, controller, harnessOptions());
  // The truth: the snapshot's head centre at every step.
  std::vector<std::pair<double, flagella::Vec3>> truth = {
      {session.time(), session.snapshot().head_position}};
  const HarnessReport report = harness.run(
      kRun, [&] { truth.emplace_back(session.time(), session.snapshot().head_position); });

  const LcmChannels ch = LcmChannels::withPrefix("FLAGELLA_");
  const long n = static_cast<long>(expected_times.size());
  EXPECT_EQ(report.published.at(ch.camera_fix), n);
  EXPECT_EQ(report.received.at(ch.camera_fix), n);
  // Every fix reached exactly one controller step, the one on the first IMU sample after its
  // instant (pending_fix.h), with the head position of its instant; the fix of the run's last
  // instant has no sample after it.
  ASSERT_EQ(static_cast<long>(controller.fixes().size()), n - 1);
  EXPECT_EQ(controller.steps(), report.received.at(ch.imu));
  for (long i = 0; i + 1 < n; ++i) {
    const FixRecordingController::Fix& fix = controller.fixes()[i];
    EXPECT_NEAR(fix.time, expected_times[i] + 1.0 / kImuRate, kStampTol) << "fix " << i;
    const double taken = expected_times[i];
    const auto at = std::min_element(truth.begin(), truth.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.first - taken) < std::abs(b.first - taken);
    });
    ASSERT_NEAR(at->first, taken, kStampTol) << "fix " << i;
    EXPECT_NEAR(fix.x, at->second.x(), kPositionTol) << "fix " << i;
    EXPECT_NEAR(fix.y, at->second.y(), kPositionTol) << "fix " << i;
  }
  // The robot moved, so equal positions mean the fixes follow the head.
  EXPECT_GT(std::hypot(controller.fixes().back().x - controller.fixes().front().x,
                       controller.fixes().back().y - controller.fixes().front().y),
            1e-4);
}

TEST(LcmHarness, CameraOffPublishesNoFixes) {
  flagella::SessionOptions options = sessionOptions();
  options.camera.rate = 0.0;
  flagella::SimSession session(config(), options);
  FixRecordingController controller(10);
  LcmHarness harness(session, controller, harnessOptions());
  const HarnessReport report = harness.run(1.0);
  const LcmChannels ch = LcmChannels::withPrefix("FLAGELLA_");
  EXPECT_EQ(report.published.at(ch.camera_fix), 0);
  EXPECT_EQ(report.received.at(ch.camera_fix), 0);
  EXPECT_TRUE(controller.fixes().empty());
  EXPECT_GT(controller.steps(), 0);
}

TEST(LcmHarness, RequestStopEndsTheRunAfterTheCurrentStep) {
  constexpr double kStopAt = 0.5;  // [s]
  flagella::SimSession session(config(), sessionOptions());
  PeriodicSwitchController controller(kOmega, kHalfPeriod, kHalfPeriod);
  LcmHarness harness(session, controller, harnessOptions());
  const HarnessReport report = harness.run(kDuration, [&] {
    if (session.time() >= kStopAt - 1e-9) harness.requestStop();
  });
  EXPECT_NEAR(report.sim_time, kStopAt, 1e-9);
  EXPECT_EQ(report.steps, std::lround(kStopAt / session.dt()));
  // The next run starts afresh.
  EXPECT_NEAR(harness.run(kStopAt).sim_time, 2.0 * kStopAt, 1e-9);
}

TEST(LcmHarness, AnUnknownProviderIsAClearError) {
  flagella::SimSession session(config(), sessionOptions());
  PeriodicSwitchController controller(kOmega, kHalfPeriod, kHalfPeriod);
  HarnessOptions options = harnessOptions();
  options.lcm_url = "nosuchprovider://";
  try {
    LcmHarness harness(session, controller, options);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://"), std::string::npos) << e.what();
  }
}

TEST(PeriodicSwitchController, RejectsUnusableSettings) {
  EXPECT_THROW(PeriodicSwitchController(0.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(PeriodicSwitchController(kOmega, -1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(PeriodicSwitchController(kOmega, 1.0, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace flagella::control
