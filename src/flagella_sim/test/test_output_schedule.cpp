// OutputSchedule: which outputs the simulator shells publish at each simulated time.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "flagella_sim/runtime/output_schedule.h"
#include "flagella_sim/runtime/sim_session.h"

namespace flagella {
namespace {

constexpr double kDt = 0.001;       // [s] simulated step
constexpr double kDuration = 10.0;  // [s]
constexpr double kTimeTol = 1e-9;   // [s] round-off of accumulated steps

using Firings = std::map<Output, std::vector<double>>;

void record(Firings& fired, const DueOutputs& due, double t) {
  if (due.rod_state) fired[Output::RodState].push_back(t);
  if (due.markers) fired[Output::Markers].push_back(t);
  if (due.path) fired[Output::Path].push_back(t);
  if (due.camera_fix) fired[Output::CameraFix].push_back(t);
  if (due.imu) fired[Output::Imu].push_back(t);
}

/// Drives the schedule like the shells do: a forced call at t = 0, then one call after each
/// step. Returns the times each output was due at after steps; checks nothing is due twice.
Firings run(OutputSchedule& schedule, double dt, double duration) {
  Firings fired;
  schedule.due(0.0, /*force=*/true);
  EXPECT_FALSE(schedule.due(0.0).any()) << "due twice at t = 0";
  const long steps = std::lround(duration / dt);
  double t = 0.0;
  for (long k = 0; k < steps; ++k) {
    t += dt;  // accumulated like the session's clock
    record(fired, schedule.due(t), t);
    if (schedule.diagnosticsDue(t)) fired[Output::Diagnostics].push_back(t);
    // Asking again at the same time: nothing is due twice.
    EXPECT_FALSE(schedule.due(t).any()) << "t = " << t;
    EXPECT_FALSE(schedule.diagnosticsDue(t)) << "t = " << t;
  }
  return fired;
}

TEST(OutputSchedule, EachOutputIsDueExactlyAtItsRate) {
  OutputRates rates;
  rates.rod_state = 20.0;
  rates.markers = 10.0;
  rates.path = 5.0;
  rates.camera_fix = 3.0;  // period not a multiple of the step
  rates.imu = 100.0;
  rates.diagnostics = 1.0;
  OutputSchedule schedule(rates);
  const Firings fired = run(schedule, kDt, kDuration);
  const std::map<Output, double> rate = {{Output::RodState, 20.0}, {Output::Markers, 10.0},
                                         {Output::Path, 5.0},      {Output::CameraFix, 3.0},
                                         {Output::Imu, 100.0},     {Output::Diagnostics, 1.0}};
  for (const auto& [output, hz] : rate) {
    const int o = static_cast<int>(output);
    ASSERT_TRUE(schedule.scheduled(output)) << o;
    const std::vector<double>& times = fired.at(output);
    // Anchored by the forced call at t = 0 (diagnostics: at the first step, which counts).
    const double t0 = output == Output::Diagnostics ? kDt : 0.0;
    const long expected = static_cast<long>(std::floor((kDuration - t0) * hz + 1e-6)) +
                          (output == Output::Diagnostics ? 1 : 0);
    ASSERT_EQ(static_cast<long>(times.size()), expected) << "output " << o;
    // Firing j: the first step at or after t0 + j / rate.
    const long first = output == Output::Diagnostics ? 0 : 1;
    for (size_t i = 0; i < times.size(); ++i) {
      const double deadline = t0 + static_cast<double>(first + static_cast<long>(i)) / hz;
      EXPECT_GE(times[i], deadline - kTimeTol) << "output " << o << " firing " << i;
      EXPECT_LT(times[i], deadline + kDt - kTimeTol) << "output " << o << " firing " << i;
    }
  }
}

TEST(OutputSchedule, AnAbsentRateIsNeverDueEvenForced) {
  OutputRates rates;
  rates.imu = 100.0;
  OutputSchedule schedule(rates);
  EXPECT_FALSE(schedule.scheduled(Output::RodState));
  EXPECT_FALSE(schedule.scheduled(Output::Diagnostics));
  const DueOutputs forced = schedule.due(0.0, true);
  EXPECT_TRUE(forced.imu);
  EXPECT_FALSE(forced.rod_state || forced.markers || forced.path || forced.camera_fix);
  EXPECT_FALSE(forced.needsSnapshot());
  const Firings fired = run(schedule, kDt, 1.0);
  EXPECT_EQ(fired.count(Output::RodState), 0u);
  EXPECT_EQ(fired.count(Output::Diagnostics), 0u);
  EXPECT_EQ(fired.at(Output::Imu).size(), 100u);
  EXPECT_FALSE(OutputSchedule().due(0.0, true).any());
}

TEST(OutputSchedule, CameraRateZeroMeansNoCameraFixes) {
  SessionOptions session;
  session.imu.rate = 50.0;
  session.camera.rate = 0.0;
  OutputSchedule off(OutputRates::forSession(session, 20.0));
  EXPECT_FALSE(off.scheduled(Output::CameraFix));
  EXPECT_FALSE(off.due(0.0, true).camera_fix);
  const Firings fired = run(off, kDt, 1.0);
  EXPECT_EQ(fired.count(Output::CameraFix), 0u);
  EXPECT_EQ(fired.at(Output::Imu).size(), 50u);
  EXPECT_EQ(fired.at(Output::RodState).size(), 20u);
  session.camera.rate = 2.0;
  OutputSchedule on(OutputRates::forSession(session, 20.0));
  EXPECT_EQ(run(on, kDt, 1.0).at(Output::CameraFix).size(), 2u);
}

TEST(OutputSchedule, AGivenRateOfZeroIsDueEveryTimeAsked) {
  // RateSchedule's meaning of rate <= 0; the shells' parameters refuse it before this point.
  OutputRates rates;
  rates.rod_state = 0.0;
  OutputSchedule schedule(rates);
  int due = 0;
  for (int k = 1; k <= 100; ++k) due += schedule.due(k * kDt).rod_state ? 1 : 0;
  EXPECT_EQ(due, 100);
}

TEST(OutputSchedule, ForcedCallsKeepTheAnchorAndRestartReanchorsAllButDiagnostics) {
  OutputRates rates;
  rates.rod_state = 10.0;
  rates.diagnostics = 10.0;
  OutputSchedule schedule(rates);
  EXPECT_TRUE(schedule.due(5.0).rod_state);
  EXPECT_TRUE(schedule.diagnosticsDue(5.0));
  EXPECT_TRUE(schedule.due(5.05, true).rod_state);  // forced
  EXPECT_FALSE(schedule.due(5.06).rod_state);       // still anchored at 5.0
  EXPECT_TRUE(schedule.due(5.1).rod_state);
  EXPECT_TRUE(schedule.diagnosticsDue(5.1));
  schedule.restart();  // a reset: the session's time starts again at 0
  EXPECT_TRUE(schedule.due(0.0).rod_state);
  EXPECT_FALSE(schedule.due(0.05).rod_state);
  EXPECT_TRUE(schedule.due(0.1).rod_state);
  EXPECT_FALSE(schedule.diagnosticsDue(0.1));  // not restarted: next due at 5.2
  EXPECT_TRUE(schedule.diagnosticsDue(5.2));
}

}  // namespace
}  // namespace flagella
