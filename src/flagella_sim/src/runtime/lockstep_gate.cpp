// The sim node's lockstep policy (ROS-free): when commands and followers let the next step run.
#include "flagella_sim/runtime/lockstep_gate.h"

namespace flagella {

namespace {
/// A follower counts as caught up within half a step of the leader's time.
bool caughtUp(const FollowerClock& f, double time, double dt) {
  return f.lost || f.time + 0.5 * dt >= time;
}
}  // namespace

LockstepGate::LockstepGate(const LockstepLimits& limits, bool wait_for_slider)
    : limits_(limits), wait_for_slider_(wait_for_slider) {}

bool LockstepGate::answers(const HeardStamp& heard, double awaited) {
  return heard.seen && heard.stamp >= awaited;
}

CommandWait LockstepGate::commands(const HeardStamp& motor, const HeardStamp& slider,
                                   double awaited, double waited) const {
  CommandWait w;
  const bool motor_answered = answers(motor, awaited);
  const bool slider_answered = !wait_for_slider_ || answers(slider, awaited);
  const bool starting = !motor.seen || (wait_for_slider_ && !slider.seen);
  w.limit = starting ? limits_.wait_timeout : limits_.lockstep_timeout;
  if (motor_answered && slider_answered) {
    w.verdict = CommandWait::Verdict::Answered;
  } else if (waited > w.limit) {
    w.verdict = CommandWait::Verdict::TimedOut;
    w.missing = motor_answered ? "slider_command" : "motor_command";
  }
  return w;
}

FollowerWait LockstepGate::followers(const std::vector<FollowerClock>& followers, double time,
                                     double dt, bool waiting, double waited) const {
  FollowerWait w;
  bool caught_up = true;
  for (const FollowerClock& f : followers) caught_up = caught_up && caughtUp(f, time, dt);
  if (caught_up) return w;
  bool starting = false;
  for (const FollowerClock& f : followers) starting = starting || (!f.lost && f.time < 0.0);
  w.limit = starting ? limits_.wait_timeout : limits_.lockstep_timeout;
  if (!waiting) {
    w.verdict = FollowerWait::Verdict::StartWaiting;
  } else if (waited > w.limit) {
    w.verdict = FollowerWait::Verdict::GiveUp;
    for (std::size_t i = 0; i < followers.size(); ++i)
      if (!followers[i].lost && followers[i].time + 0.5 * dt < time) w.behind.push_back(i);
  } else {
    w.verdict = FollowerWait::Verdict::Waiting;
  }
  return w;
}

}  // namespace flagella
