// Decides which periodic outputs of the simulator shells (ROS node, LCM shell) are due when.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "flagella_sim/runtime/rate_schedule.h"

namespace flagella {

struct SessionOptions;

/// The periodic outputs a shell publishes. Diagnostics are asked apart (only after steps).
enum class Output { RodState, Markers, Path, CameraFix, Imu, Diagnostics };

/// Rates in Hz of simulated time, as RateSchedule takes them (<= 0: due every time asked).
/// An absent rate: the shell has no such output, never due.
struct OutputRates {
  std::optional<double> rod_state, markers, path, camera_fix, imu, diagnostics;
  /// The session's outputs: the IMU at imu.rate, camera fixes at camera.rate when the camera
  /// is enabled (rate > 0; absent otherwise), the rod state at `state_rate`.
  static OutputRates forSession(const SessionOptions& session, double state_rate);
};

/// What is due at one instant.
struct DueOutputs {
  bool rod_state = false, markers = false, path = false, camera_fix = false, imu = false;
  bool any() const { return rod_state || markers || path || camera_fix || imu; }
  /// Outputs read from a RodSnapshot.
  bool needsSnapshot() const { return rod_state || markers || path; }
};

class OutputSchedule {
 public:
  OutputSchedule() = default;  ///< no outputs
  explicit OutputSchedule(const OutputRates& rates);
  /// Which outputs are due at `time`: every scheduled output's schedule is advanced (a forced
  /// call too, so the schedules stay anchored); `force` makes every scheduled output due.
  /// Diagnostics are not included (see diagnosticsDue).
  DueOutputs due(double time, bool force = false);
  /// True once per diagnostics period; never without a diagnostics rate.
  bool diagnosticsDue(double time);
  /// Re-anchors every schedule but the diagnostics' at the next call (after a reset).
  void restart();
  bool scheduled(Output output) const { return slot(output).has_value(); }

 private:
  static constexpr std::size_t kOutputs = 6;
  std::optional<RateSchedule>& slot(Output o) { return schedules_[static_cast<std::size_t>(o)]; }
  const std::optional<RateSchedule>& slot(Output o) const {
    return schedules_[static_cast<std::size_t>(o)];
  }
  bool ask(Output output, double time, bool force);

  std::array<std::optional<RateSchedule>, kOutputs> schedules_;
};

}  // namespace flagella
