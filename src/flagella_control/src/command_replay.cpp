// Open-loop replay of recorded commands; see the header.
#include "flagella_control/command_replay.h"

#include <stdexcept>

namespace flagella::control {

CommandReplayController::CommandReplayController(std::vector<RecordedCommand> commands,
                                                 double rest_slider)
    : commands_(std::move(commands)), rest_slider_(rest_slider) {
  if (commands_.empty()) throw std::invalid_argument("command replay: no recorded command");
  for (std::size_t i = 1; i < commands_.size(); ++i)
    if (!(commands_[i].time >= commands_[i - 1].time))
      throw std::invalid_argument("command replay: commands not in time order at index " +
                                  std::to_string(i));
}

void CommandReplayController::reset() {
  started_ = finished_ = false;
  start_time_ = 0.0;
  next_ = 0;
}

ControllerOutputs CommandReplayController::step(const ControllerInputs& in) {
  ControllerOutputs out;
  out.slider_valid = true;
  out.slider_position = rest_slider_;
  if (!started_) {
    started_ = true;
    start_time_ = in.time;
  }
  const double t = in.time - start_time_;
  // Small slack: the recording's and the replay's clocks are sums of the same dt.
  while (next_ < commands_.size() && commands_[next_].time <= t + 1e-9) ++next_;
  if (next_ == commands_.size() && t > commands_.back().time + 1e-9) finished_ = true;
  if (finished_) {
    out.mode = ControllerMode::Finished;
    return out;
  }
  const RecordedCommand& c = commands_[next_ == 0 ? 0 : next_ - 1];
  out.motor_command = c.motor;
  out.slider_position = c.slider;
  out.mode = ControllerMode::Running;
  return out;
}

CommandRecorder::CommandRecorder(ControllerCore& inner, std::size_t capacity) : inner_(inner) {
  commands_.reserve(capacity);
}

void CommandRecorder::reset() {
  inner_.reset();
  commands_.clear();
  started_ = false;
}

ControllerOutputs CommandRecorder::step(const ControllerInputs& in) {
  const ControllerOutputs out = inner_.step(in);
  if (!started_) {
    started_ = true;
    start_time_ = in.time;
  }
  commands_.push_back({in.time - start_time_, out.motor_command, out.slider_position});
  return out;
}

}  // namespace flagella::control
