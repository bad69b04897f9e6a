// Reading the YAML metadata file of a measured data set: typed fields with error positions.
#include "metadata.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "csv.h"
#include "data_io_names.h"
#include "flagella_identify/data_error.h"
#include "flagella_sim/core/strict_map.h"
#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/core/text_lists.h"
#include "text_format.h"

namespace flagella {
namespace identify {
namespace data_io {

namespace fs = std::filesystem;

void Metadata::fail(const YAML::Node& at, const std::string& message) const {
  int line = 0;
  int column = 0;
  if (at.IsDefined()) {
    const YAML::Mark mark = at.Mark();
    if (mark.line >= 0) {
      line = mark.line + 1;
      column = mark.column + 1;
    }
  }
  throw DataError(file_, line, column, message);
}

void Metadata::rejectUnknownKeys(const YAML::Node& map, const std::string& prefix,
                                 const std::vector<std::string>& allowed) const {
  const StrictMap strict(map, prefix);
  for (const std::string& key : allowed) strict.markKnown(key);
  if (const std::optional<YAML::Node> unknown = strict.firstUnknownKey())
    fail(*unknown, "unknown key '" + prefix + abbreviated(keyText(*unknown, prefix)) +
                       "' (allowed: " + joined(allowed, ", ") + ")");
}

std::string Metadata::keyText(const YAML::Node& key, const std::string& prefix) const {
  if (!key.IsScalar())
    fail(key, "keys of " + (prefix.empty() ? "the metadata" : prefix) + " must be plain names");
  return key.Scalar();
}

YAML::Node Metadata::get(const std::string& key) const {
  YAML::Node node = root_[key];
  if (!node.IsDefined() || node.IsNull()) return YAML::Node(YAML::NodeType::Undefined);
  return node;
}

YAML::Node Metadata::keyNode(const std::string& key) const {
  for (const auto& kv : root_)
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.first;
  return root_;
}

std::string Metadata::text(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field + ": expected a text value");
  return node.Scalar();
}

double Metadata::number(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field + ": expected a number");
  const std::optional<double> value = csv::parseNumber(node.Scalar());
  if (!value) fail(node, field + ": expected a number, got '" + abbreviated(node.Scalar()) + "'");
  if (!std::isfinite(*value))
    fail(node, field + ": expected a finite number, got '" + abbreviated(node.Scalar()) + "'");
  return *value;
}

double Metadata::positive(const YAML::Node& node, const std::string& field) const {
  const double value = number(node, field);
  if (!(value > 0.0)) fail(node, field + " must be > 0, got " + csv::formatNumber(value));
  return value;
}

double Metadata::inRange(const YAML::Node& node, const std::string& field, double min,
                         bool min_allowed, double max, const std::string& unit) const {
  const double value = number(node, field);
  const bool above = min_allowed ? value >= min : value > min;
  if (!above || !(value <= max))
    fail(node, field + " must be in " + (min_allowed ? "[" : "(") + csv::formatNumber(min) + ", " +
                   csv::formatNumber(max) + "] " + unit + ", got " + csv::formatNumber(value));
  return value;
}

std::string Metadata::requiredText(const std::string& key) const {
  const YAML::Node node = get(key);
  if (!node.IsDefined()) fail(root_, "missing required key '" + key + "'");
  return text(node, key);
}

std::string Metadata::filePath(const std::string& key) const {
  const std::string name = requiredText(key);
  if (name.empty()) fail(get(key), key + ": expected a file name");
  fs::path path(name);
  if (path.is_relative()) path = fs::path(file_).parent_path() / path;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    fail(get(key), key + ": cannot open '" + abbreviated(path.string(), kMaxListedText) + "' (" +
                       (fs::exists(path, ec) ? "not a regular file" : "no such file") +
                       "; paths are relative to the metadata file's directory)");
  return path.string();
}

std::vector<ConfigOverride> Metadata::overrides() const {
  std::vector<ConfigOverride> out;
  const YAML::Node node = get("overrides");
  if (!node.IsDefined()) return out;
  if (!node.IsMap()) fail(node, "overrides: expected a map of \"section.field\": value");
  for (const auto& kv : node) {
    const std::string name = keyText(kv.first, "overrides");
    const std::string problem = overrideNameProblem(name);
    if (!problem.empty()) fail(kv.first, "override '" + abbreviated(name) + "' " + problem);
    const YAML::Node& value = kv.second;
    if (!value.IsDefined() || value.IsNull())
      fail(kv.first, "override '" + abbreviated(name) + "' has no value");
    if (value.IsScalar()) {
      out.emplace_back(name, value.Scalar());
    } else {
      YAML::Emitter emitter;
      emitter << YAML::Flow << value;
      out.emplace_back(name, emitter.c_str());
    }
  }
  return out;
}

std::map<std::string, double> Metadata::noise(const std::vector<std::string>& allowed) const {
  std::map<std::string, double> out;
  const YAML::Node node = get("noise");
  if (!node.IsDefined()) return out;
  if (!node.IsMap()) fail(node, "noise: expected a map of name: standard deviation");
  rejectUnknownKeys(node, "noise.", allowed);
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (!kv.second.IsDefined() || kv.second.IsNull())
      fail(kv.first, "noise." + key + " has no value; expected a number > 0");
    out[key] = positive(kv.second, "noise." + key);
  }
  return out;
}

void Metadata::requireNoise(const std::map<std::string, double>& noise, const std::string& key,
                            const std::string& why) const {
  if (noise.count(key)) return;
  fail(keyNode("noise"), "noise." + key + " is required: " + why);
}

Metadata loadMetadata(const std::string& path) {
  YAML::Node root;
  try {
    root = loadStrictYamlFile(path, "metadata");
  } catch (const YamlInputError& e) {
    throw DataError(path, e.line(), e.column(), e.message());
  }
  Metadata meta(path, root);
  if (!root.IsMap()) meta.fail(root, "expected a map of metadata fields (kind, csv, noise, ...)");
  return meta;
}

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
