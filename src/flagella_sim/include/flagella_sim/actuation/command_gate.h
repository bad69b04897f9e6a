// Validation of a stream of set-points (motor rate, slider position) arriving from outside:
// non-finite and out-of-range values are rejected and the last valid one is kept; optionally a
// firmware-style failsafe drops the output to a safe value when the stream goes quiet.
#pragma once

#include <string>

namespace flagella {

struct CommandGateOptions {
  std::string field = "command";  ///< name used in rejection messages
  std::string unit;               ///< unit used in rejection messages
  double min = -1.0;              ///< allowed range, inclusive
  double max = 1.0;
  double safe_value = 0.0;  ///< output before the first command and when the failsafe trips
  double timeout = 0.0;     ///< failsafe after this long without a valid command [s]; 0: never
};

enum class CommandVerdict { Accepted, NotFinite, OutOfRange };

class CommandGate {
 public:
  /// Throws std::invalid_argument if the options are inconsistent.
  explicit CommandGate(CommandGateOptions options);

  /// Offers a value received at time `now`; a rejected value leaves the output unchanged.
  CommandVerdict submit(double value, double now);
  /// The value to apply at time `now`: the last valid one, or safe_value if none was ever
  /// accepted or the failsafe has tripped.
  double output(double now) const;
  bool hasCommand() const { return has_command_; }
  bool failsafeTripped(double now) const;
  /// Forgets every command (back to the state after construction).
  void clear();

  long acceptedCount() const { return accepted_; }
  long rejectedCount() const { return rejected_; }
  /// Message naming the field, the value and the allowed range, for the last rejection.
  const std::string& lastRejection() const { return last_rejection_; }
  const CommandGateOptions& options() const { return options_; }

 private:
  CommandGateOptions options_;
  bool has_command_ = false;
  double value_ = 0.0;
  double last_time_ = 0.0;
  long accepted_ = 0;
  long rejected_ = 0;
  std::string last_rejection_;
};

}  // namespace flagella
