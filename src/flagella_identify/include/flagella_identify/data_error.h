// Errors in measured-data files: every message starts with the position of the problem,
// "file:line:column: " (1-based), or just "file: " when no position applies.
#pragma once

#include <string>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {
namespace identify {

class DataError : public ConfigError {
 public:
  /// `line` and `column` are 1-based; pass 0 for both when no position applies, 0 for the
  /// column when the message is about a whole line. For CSV cells
  /// the column is the 1-based field index, for YAML the column of the mark.
  DataError(const std::string& file, int line, int column, const std::string& message)
      : ConfigError(location(file, line, column) + message),
        file_(file),
        line_(line),
        column_(column),
        message_(message) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  /// The message without the position prefix.
  const std::string& message() const { return message_; }

  /// "file:line:column: ", "file:line: " when the column is 0 (a whole row), or "file: " when
  /// line and column are both 0.
  static std::string location(const std::string& file, int line, int column) {
    if (line <= 0 && column <= 0) return file + ": ";
    if (column <= 0) return file + ":" + std::to_string(line) + ": ";
    return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
  }

 private:
  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string message_;
};

}  // namespace identify
}  // namespace flagella
