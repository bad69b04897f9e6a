// Strict YAML input for every file the tools read (configs, sweep files, paths and waypoints,
// calibrations, dataset metadata) and for values given on command lines: exactly one document,
// not empty; no map holding a key twice (yaml-cpp keeps both and answers lookups with the
// first, so a later NaN would be silently ignored); no application tag (!name), whose meaning
// nothing here would honour. Errors name the source and the line.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "flagella_sim/core/config_error.h"

namespace flagella {

/// A file or text that is not one well-formed, strict YAML document.
class YamlInputError : public ConfigError {
 public:
  /// `line` and `column` are 1-based, 0 when unknown; what() reads
  /// "SOURCE: line L, column C: message".
  YamlInputError(const std::string& source, int line, int column, const std::string& message);
  const std::string& source() const { return source_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& message() const { return message_; }

 private:
  std::string source_;
  int line_, column_;
  std::string message_;
};

/// Reads and parses `path`; `what` names the kind of file in messages ("config", "sweep").
YAML::Node loadStrictYamlFile(const std::string& path, const std::string& what);
/// Parses `text` as one value (null allowed: ~ or null); messages name `source`.
YAML::Node loadStrictYamlText(const std::string& text, const std::string& source);
/// The checks on an already parsed tree: duplicate keys and application tags, at any depth.
void checkStrictYaml(const YAML::Node& root, const std::string& source);

}  // namespace flagella
