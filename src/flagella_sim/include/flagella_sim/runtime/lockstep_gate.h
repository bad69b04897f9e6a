// The sim node's lockstep policy (ROS-free): may the next step run, has a wait timed out.
#pragma once

#include <cstddef>
#include <vector>

namespace flagella {

/// The newest stamp heard on one command topic.
struct HeardStamp {
  bool seen = false;
  double stamp = 0.0;  ///< [s], valid when seen
};

/// A follower's clock as the leader last heard it.
struct FollowerClock {
  double time = -1.0;  ///< [s simulated] latest time heard; < 0: none yet
  bool lost = false;   ///< given up on: no longer waited for
};

/// How long a wait may last [s wall].
struct LockstepLimits {
  double wait_timeout = 30.0;     ///< for a peer not heard from yet (it may still be starting up)
  double lockstep_timeout = 5.0;  ///< for a peer heard from before that stalls mid-run
};

/// The verdict on a wait for the commands answering an IMU sample.
struct CommandWait {
  enum class Verdict { Waiting, Answered, TimedOut };
  Verdict verdict = Verdict::Waiting;
  double limit = 0.0;  ///< [s wall] the limit that applies to this wait
  /// On TimedOut: the topic not answered ("motor_command", else "slider_command").
  const char* missing = "";
};

/// The verdict on a wait for the followers to reach the leader's time.
struct FollowerWait {
  enum class Verdict { CaughtUp, StartWaiting, Waiting, GiveUp };
  Verdict verdict = Verdict::CaughtUp;
  double limit = 0.0;  ///< [s wall] the limit that applies to this wait
  /// On GiveUp: indices of the followers still behind, to be marked lost.
  std::vector<std::size_t> behind;
};

class LockstepGate {
 public:
  /// `wait_for_slider`: a slider command must answer each IMU sample as well as a motor command.
  LockstepGate(const LockstepLimits& limits, bool wait_for_slider);

  /// True when `heard` carries a stamp at or after `awaited` [s].
  static bool answers(const HeardStamp& heard, double awaited);

  /// The wait for commands stamped >= `awaited` [s], `waited` [s wall] after it began. A
  /// controller not heard from yet gets wait_timeout, one heard from before lockstep_timeout.
  CommandWait commands(const HeardStamp& motor, const HeardStamp& slider, double awaited,
                       double waited) const;

  /// The wait for `followers` to reach `time` [s] (within half of the step `dt` [s]). `waiting`:
  /// a wait began `waited` [s wall] ago; it times out only after it has begun. A follower still
  /// starting up (nothing heard) gets wait_timeout, one that stalls mid-run lockstep_timeout.
  FollowerWait followers(const std::vector<FollowerClock>& followers, double time, double dt,
                         bool waiting, double waited) const;

 private:
  LockstepLimits limits_;
  bool wait_for_slider_;
};

}  // namespace flagella
