// The error types for bad user input (configs, overrides, command lines, input files): the tools
// report them and exit 2.
#pragma once

#include <stdexcept>

namespace flagella {

/// Error in user input (config, override, command line): the message names the field and the
/// allowed range.
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// An input file that cannot be read as its kind (a path, a calibration, a waypoint mission):
/// bad input like ConfigError (the tools exit 2), but a std::runtime_error, as the control
/// package's load errors are.
class InputFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace flagella
