// Open-loop replay of a recorded command schedule (the baseline of the robustness runs,
// docs/model.md 7.4): the motor and slider commands a controller gave on the nominal model, played
// back by time with no feedback. ControllerCore contract: fixed step, no heap allocation in step().
#pragma once

#include <vector>

#include "flagella_control/controller_core.h"

namespace flagella::control {

struct RecordedCommand {
  double time = 0.0;  ///< [s] from the first step of the recording
  double motor = 0.0;
  double slider = 0.0;
};

class CommandReplayController : public ControllerCore {
 public:
  /// `commands` in time order (std::invalid_argument otherwise, or if empty); `rest_slider` is
  /// held before the first step and after the last command.
  CommandReplayController(std::vector<RecordedCommand> commands, double rest_slider);
  /// The command recorded last at or before the time since the first step; after the last
  /// command: motor stopped, slider at rest, mode Finished.
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return "open_loop_replay"; }
  bool finished() const { return finished_; }

 private:
  std::vector<RecordedCommand> commands_;
  double rest_slider_;
  bool started_ = false, finished_ = false;
  double start_time_ = 0.0;
  std::size_t next_ = 0;
};

/// Wraps a controller and records every output it gives (for a later replay).
class CommandRecorder : public ControllerCore {
 public:
  /// `capacity`: steps reserved up front so that step() does not allocate below it.
  CommandRecorder(ControllerCore& inner, std::size_t capacity);
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return inner_.name(); }
  const std::vector<RecordedCommand>& commands() const { return commands_; }

 private:
  ControllerCore& inner_;
  std::vector<RecordedCommand> commands_;
  bool started_ = false;
  double start_time_ = 0.0;
};

}  // namespace flagella::control
