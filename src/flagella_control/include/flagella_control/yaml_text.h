// Strict reading and tidy writing of the controller library's YAML files (calibrations):
// every field read once, unknown fields rejected, errors naming the file and the field; numbers
// written as the shortest text that reads back to the same double.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "flagella_sim/core/strict_map.h"

namespace flagella::control {

/// Shortest decimal that reads back to exactly the same double (.nan/.inf for non-finite).
std::string numberText(double x);
/// A double-quoted YAML string with escapes.
std::string quotedText(const std::string& s);
/// "key: value" indented, padded to a column and followed by "# comment" when one is given.
std::string commentedLine(int indent, const std::string& key_value, const std::string& comment);

/// Writes `text` to `path` (std::runtime_error naming the file if it cannot).
void writeTextFile(const std::string& path, const std::string& text);

/// Loads `path` and returns its only top-level entry `key` (std::runtime_error naming the file
/// and the field otherwise; `what` names the kind of file in messages, e.g. "calibration").
YAML::Node loadSingleKeyFile(const std::string& path, const std::string& key,
                             const std::string& what);

/// Strict reader of one YAML map: every key read once, unknown keys rejected.
class MapReader {
 public:
  /// `what` names the kind of file in messages ("calibration field 'a.b' is missing").
  MapReader(const YAML::Node& node, std::string path, std::string file, std::string what);

  [[noreturn]] void fail(const std::string& field, const std::string& what) const;
  std::string field(const std::string& key) const { return map_.path() + "." + key; }
  YAML::Node get(const std::string& key);
  bool has(const std::string& key) const { return map_.contains(key); }
  double number(const std::string& key) { return parseNumber(get(key), field(key)); }
  double parseNumber(const YAML::Node& n, const std::string& name) const;
  std::string string(const std::string& key);
  MapReader child(const std::string& key) { return MapReader(get(key), field(key), file_, what_); }
  void rejectUnknown() const;

 private:
  StrictMap map_;  ///< the map and the keys read
  std::string file_, what_;
};

}  // namespace flagella::control
