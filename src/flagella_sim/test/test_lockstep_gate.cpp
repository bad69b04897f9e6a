// LockstepGate against hand-worked cases: commands answering, wait limits, followers catching up.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "flagella_sim/runtime/lockstep_gate.h"

namespace flagella {
namespace {

// Binary-exact numbers, so that the boundary cases ("waited == limit") hold exactly.
constexpr double kWaitTimeout = 2.0;      // [s wall] a peer not heard from yet
constexpr double kLockstepTimeout = 0.5;  // [s wall] a peer that stalls mid-run
constexpr double kAwaited = 1.0;          // [s] stamp of the IMU sample waited for
constexpr double kEarlier = 0.75;         // [s] a stamp before kAwaited
constexpr double kLater = 1.25;           // [s] a stamp after kAwaited
constexpr double kEpsilon = 1e-9;         // [s] smallest step past a boundary that must count
constexpr double kDt = 0.25;              // [s] simulated step: half of it is 0.125
constexpr double kLeader = 1.0;           // [s] the leader's simulated time

using CVerdict = CommandWait::Verdict;
using FVerdict = FollowerWait::Verdict;

LockstepGate gate(bool wait_for_slider = false) {
  return LockstepGate({kWaitTimeout, kLockstepTimeout}, wait_for_slider);
}

HeardStamp heard(double stamp) { return {true, stamp}; }
const HeardStamp kNothing{};

TEST(LockstepGate, AnswersNeedsAStampAtOrAfterTheAwaitedOne) {
  EXPECT_TRUE(LockstepGate::answers(heard(kAwaited), kAwaited));
  EXPECT_TRUE(LockstepGate::answers(heard(kLater), kAwaited));
  EXPECT_FALSE(LockstepGate::answers(heard(kEarlier), kAwaited));
  EXPECT_FALSE(LockstepGate::answers(heard(kAwaited - kEpsilon), kAwaited));
  // Nothing heard: no answer, whatever the stored stamp.
  EXPECT_FALSE(LockstepGate::answers(HeardStamp{false, kLater}, kAwaited));
}

TEST(LockstepGate, MotorCommandAnsweringTheSampleLetsTheStepRun) {
  // Even after a long wait: an answer is an answer, not a timeout.
  const CommandWait w = gate().commands(heard(kAwaited), kNothing, kAwaited, 100.0);
  EXPECT_EQ(w.verdict, CVerdict::Answered);
}

TEST(LockstepGate, StaleMotorCommandWaitsUpToTheLockstepTimeout) {
  const CommandWait below = gate().commands(heard(kEarlier), kNothing, kAwaited, 0.25);
  EXPECT_EQ(below.verdict, CVerdict::Waiting);
  EXPECT_EQ(below.limit, kLockstepTimeout);
  // The limit itself is still within the wait; just past it is a timeout.
  EXPECT_EQ(gate().commands(heard(kEarlier), kNothing, kAwaited, kLockstepTimeout).verdict,
            CVerdict::Waiting);
  const CommandWait above =
      gate().commands(heard(kEarlier), kNothing, kAwaited, kLockstepTimeout + kEpsilon);
  EXPECT_EQ(above.verdict, CVerdict::TimedOut);
  EXPECT_EQ(above.limit, kLockstepTimeout);
  EXPECT_EQ(std::string(above.missing), "motor_command");
}

TEST(LockstepGate, ControllerNotHeardYetGetsTheWaitTimeout) {
  // 1 s: past the lockstep timeout but within the start-up allowance.
  const CommandWait starting = gate().commands(kNothing, kNothing, kAwaited, 1.0);
  EXPECT_EQ(starting.verdict, CVerdict::Waiting);
  EXPECT_EQ(starting.limit, kWaitTimeout);
  EXPECT_EQ(gate().commands(kNothing, kNothing, kAwaited, kWaitTimeout).verdict, CVerdict::Waiting);
  const CommandWait late = gate().commands(kNothing, kNothing, kAwaited, kWaitTimeout + kEpsilon);
  EXPECT_EQ(late.verdict, CVerdict::TimedOut);
  EXPECT_EQ(std::string(late.missing), "motor_command");
}

TEST(LockstepGate, SliderIsIgnoredUnlessWaitedFor) {
  // Not waited for: a slider never heard neither holds the step nor counts as starting up.
  EXPECT_EQ(gate(false).commands(heard(kAwaited), kNothing, kAwaited, 0.0).verdict,
            CVerdict::Answered);
  EXPECT_EQ(gate(false).commands(heard(kEarlier), kNothing, kAwaited, 1.0).verdict,
            CVerdict::TimedOut);
}

TEST(LockstepGate, WaitedForSliderMustAnswerToo) {
  const LockstepGate g = gate(true);
  EXPECT_EQ(g.commands(heard(kAwaited), heard(kLater), kAwaited, 0.0).verdict, CVerdict::Answered);
  const CommandWait stale = g.commands(heard(kAwaited), heard(kEarlier), kAwaited, 0.25);
  EXPECT_EQ(stale.verdict, CVerdict::Waiting);
  EXPECT_EQ(stale.limit, kLockstepTimeout);
  const CommandWait timed_out =
      g.commands(heard(kAwaited), heard(kEarlier), kAwaited, kLockstepTimeout + kEpsilon);
  EXPECT_EQ(timed_out.verdict, CVerdict::TimedOut);
  EXPECT_EQ(std::string(timed_out.missing), "slider_command");
  // Both missing: the motor command is named.
  EXPECT_EQ(std::string(g.commands(heard(kEarlier), heard(kEarlier), kAwaited, 1.0).missing),
            "motor_command");
  // A slider not heard yet: start-up allowance although the motor was heard.
  const CommandWait starting = g.commands(heard(kAwaited), kNothing, kAwaited, 1.0);
  EXPECT_EQ(starting.verdict, CVerdict::Waiting);
  EXPECT_EQ(starting.limit, kWaitTimeout);
}

TEST(LockstepGate, FollowersWithinHalfAStepAreCaughtUp) {
  EXPECT_EQ(gate().followers({}, kLeader, kDt, false, 0.0).verdict, FVerdict::CaughtUp);
  // 0.875 + 0.125 == 1.0: exactly at the boundary.
  const std::vector<FollowerClock> at_boundary{{0.875, false}, {kLeader, false}};
  EXPECT_EQ(gate().followers(at_boundary, kLeader, kDt, true, 100.0).verdict, FVerdict::CaughtUp);
  // A lost follower is not waited for, however far behind.
  const std::vector<FollowerClock> lost{{0.0, true}, {kLeader, false}};
  EXPECT_EQ(gate().followers(lost, kLeader, kDt, false, 0.0).verdict, FVerdict::CaughtUp);
}

TEST(LockstepGate, FollowerBehindStartsThenTimesAWait) {
  const std::vector<FollowerClock> behind{{kLeader, false}, {0.75, false}};
  // Not waiting yet: the wait begins, however long ago the caller's clock was set.
  const FollowerWait start = gate().followers(behind, kLeader, kDt, false, 100.0);
  EXPECT_EQ(start.verdict, FVerdict::StartWaiting);
  EXPECT_EQ(start.limit, kLockstepTimeout);
  EXPECT_TRUE(start.behind.empty());
  EXPECT_EQ(gate().followers(behind, kLeader, kDt, true, kLockstepTimeout).verdict,
            FVerdict::Waiting);
  const FollowerWait give_up =
      gate().followers(behind, kLeader, kDt, true, kLockstepTimeout + kEpsilon);
  EXPECT_EQ(give_up.verdict, FVerdict::GiveUp);
  EXPECT_EQ(give_up.behind, std::vector<std::size_t>{1});
  // Just behind the half-step boundary counts as behind.
  const std::vector<FollowerClock> just_behind{{0.875 - kEpsilon, false}};
  EXPECT_EQ(gate().followers(just_behind, kLeader, kDt, true, 0.0).verdict, FVerdict::Waiting);
}

TEST(LockstepGate, FollowerNotHeardYetGetsTheWaitTimeout) {
  // Index 0 caught up, 1 behind, 2 never heard, 3 lost (skipped).
  const std::vector<FollowerClock> mixed{
      {kLeader, false}, {0.5, false}, {-1.0, false}, {0.25, true}};
  const FollowerWait waiting = gate().followers(mixed, kLeader, kDt, true, 1.0);
  EXPECT_EQ(waiting.verdict, FVerdict::Waiting);
  EXPECT_EQ(waiting.limit, kWaitTimeout);
  const FollowerWait give_up = gate().followers(mixed, kLeader, kDt, true, kWaitTimeout + kEpsilon);
  EXPECT_EQ(give_up.verdict, FVerdict::GiveUp);
  EXPECT_EQ(give_up.behind, (std::vector<std::size_t>{1, 2}));
  // A lost follower never heard from does not earn the start-up allowance.
  const std::vector<FollowerClock> lost_silent{{0.5, false}, {-1.0, true}};
  EXPECT_EQ(gate().followers(lost_silent, kLeader, kDt, true, 1.0).verdict, FVerdict::GiveUp);
}

}  // namespace
}  // namespace flagella
