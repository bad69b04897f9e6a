// Library-internal: the YAML metadata file of a measured data set, read with error positions.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "flagella_identify/measured_data.h"

namespace flagella {
namespace identify {
namespace data_io {

/// Metadata of one file: the error positions come from the YAML marks.
class Metadata {
 public:
  Metadata(std::string file, YAML::Node root) : file_(std::move(file)), root_(std::move(root)) {}

  const std::string& file() const { return file_; }
  const YAML::Node& root() const { return root_; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& message) const;

  /// Throws for a key of `map` (field path `prefix`) that is not in `allowed`.
  void rejectUnknownKeys(const YAML::Node& map, const std::string& prefix,
                         const std::vector<std::string>& allowed) const;

  std::string keyText(const YAML::Node& key, const std::string& prefix) const;

  /// The node of a key of the root map (invalid/undefined if absent or null).
  YAML::Node get(const std::string& key) const;

  bool has(const std::string& key) const { return get(key).IsDefined(); }

  /// The key node of a root key (for messages about the key as a whole); the root if absent.
  YAML::Node keyNode(const std::string& key) const;

  std::string text(const YAML::Node& node, const std::string& field) const;
  double number(const YAML::Node& node, const std::string& field) const;
  double positive(const YAML::Node& node, const std::string& field) const;
  /// A number above `min` (or equal to it if `min_allowed`) and at most `max` (`unit` for
  /// messages).
  double inRange(const YAML::Node& node, const std::string& field, double min, bool min_allowed,
                 double max, const std::string& unit) const;
  std::string requiredText(const std::string& key) const;

  /// The path a file key names, relative to the metadata file's directory; it must exist.
  std::string filePath(const std::string& key) const;

  /// The "overrides" map: "section.field": value (scalar or flow text of a list/map).
  std::vector<ConfigOverride> overrides() const;

  /// The "noise" map with its keys checked against `allowed`, values > 0 (in file units).
  std::map<std::string, double> noise(const std::vector<std::string>& allowed) const;

  /// Throws unless noise `key` is given; `why` says which data needs it.
  void requireNoise(const std::map<std::string, double>& noise, const std::string& key,
                    const std::string& why) const;

 private:
  std::string file_;
  YAML::Node root_;
};

/// Loads a metadata file: it must exist, parse as YAML and hold a map (kind not checked).
Metadata loadMetadata(const std::string& path);

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
