// Strict reading of YAML maps: every field is declared with its allowed range, unknown fields
// are errors, and every message names the full dotted field path.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/strict_map.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/core/types.h"

namespace flagella {

/// One field a FieldReader was asked for, as `flagella_run robots` and the README list it.
struct FieldSchema {
  std::string field;     ///< dotted name
  std::string fallback;  ///< the default, as text ("" for none)
  std::string range;     ///< "[min, max]", "one of: a, b", "true or false", ...
  std::string unit;
};

class FieldReader {
 public:
  /// `node` must be a map or absent; `path` is its dotted name ("robot", "effects.rft").
  FieldReader(const YAML::Node& node, std::string path);

  bool has(const std::string& key) const;
  double number(const std::string& key, double fallback, double min, double max,
                const std::string& unit = "");
  int integer(const std::string& key, int fallback, int min, int max);
  bool flag(const std::string& key, bool fallback);
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed);
  Vec3 vector3(const std::string& key, const Vec3& fallback);
  std::vector<double> numberList(const std::string& key, double min, double max);
  FieldReader child(const std::string& key);
  /// Keys of the map (for maps whose keys are names, e.g. the effects list).
  std::vector<std::string> keys() const;
  const std::string& path() const { return map_.path(); }
  /// The dotted name of `key` in messages (a long key abbreviated: it may be any user text).
  std::string field(const std::string& key) const {
    return path().empty() ? abbreviated(key) : path() + "." + abbreviated(key);
  }

  /// Throws ConfigError if the map holds a key nothing asked for.
  void rejectUnknown() const;

  /// Every later read (of this reader and its children) also appends the field's schema to
  /// `sink` (nullptr: stop); reading an empty section so lists a parser's fields and defaults.
  void recordSchema(std::vector<FieldSchema>* sink) { schema_ = sink; }
  /// Appends a field to the schema being recorded without reading it (a field read only in
  /// some cases, e.g. one of two exclusive fields).
  void describe(const std::string& key, std::string fallback, std::string range,
                std::string unit = "");

 private:
  YAML::Node get(const std::string& key) { return map_.take(key); }
  StrictMap map_;  ///< the section and the fields asked for (has() included)
  std::vector<FieldSchema>* schema_ = nullptr;
};

/// Sets the value at a dotted path ("robot.n_tails") in a YAML tree from a string, creating
/// intermediate maps; the value is parsed as YAML (numbers, lists, strings).
void applyOverride(YAML::Node& root, const std::string& assignment);

}  // namespace flagella
