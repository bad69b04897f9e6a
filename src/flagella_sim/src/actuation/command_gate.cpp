#include "flagella_sim/actuation/command_gate.h"

#include <cmath>
#include <stdexcept>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

CommandGate::CommandGate(CommandGateOptions options) : options_(std::move(options)) {
  if (!(options_.min <= options_.max))
    throw std::invalid_argument(options_.field + ": empty allowed range [" +
                                std::to_string(options_.min) + ", " + std::to_string(options_.max) +
                                "]");
  if (!(options_.safe_value >= options_.min && options_.safe_value <= options_.max))
    throw std::invalid_argument(options_.field + ": safe value outside the allowed range");
  if (!(options_.timeout >= 0.0) || !std::isfinite(options_.timeout))
    throw std::invalid_argument(options_.field + ": failsafe timeout must be finite and >= 0");
}

CommandVerdict CommandGate::submit(double value, double now) {
  if (!std::isfinite(value)) {
    ++rejected_;
    last_rejection_ = options_.field + " = " + std::to_string(value) +
                      " is not a finite number; keeping the last valid command";
    return CommandVerdict::NotFinite;
  }
  if (value < options_.min || value > options_.max) {
    ++rejected_;
    last_rejection_ =
        rangeMessage(options_.field, value, options_.min, options_.max, options_.unit) +
        "; keeping the last valid command";
    return CommandVerdict::OutOfRange;
  }
  ++accepted_;
  has_command_ = true;
  value_ = value;
  last_time_ = now;
  return CommandVerdict::Accepted;
}

bool CommandGate::failsafeTripped(double now) const {
  return has_command_ && options_.timeout > 0.0 && now - last_time_ > options_.timeout;
}

double CommandGate::output(double now) const {
  if (!has_command_ || failsafeTripped(now)) return options_.safe_value;
  return value_;
}

void CommandGate::clear() {
  has_command_ = false;
  value_ = options_.safe_value;
  last_time_ = 0.0;
  accepted_ = rejected_ = 0;
  last_rejection_.clear();
}

}  // namespace flagella
