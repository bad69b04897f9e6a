#include "flagella_sim/core/yaml_fields.h"

#include <cmath>
#include <sstream>

#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/core/text_lists.h"

namespace flagella {

namespace {
std::string where(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.line < 0) return "";
  return " (line " + std::to_string(m.line + 1) + ", column " + std::to_string(m.column + 1) + ")";
}
}  // namespace

FieldReader::FieldReader(const YAML::Node& node, std::string path) : map_(node, std::move(path)) {
  if (node && !node.IsNull() && !node.IsMap())
    throw ConfigError((this->path().empty() ? std::string("the config") : this->path()) +
                      " must be a map of fields" + where(node));
}

bool FieldReader::has(const std::string& key) const {
  map_.markKnown(key);  // asked about: a known field (given as null it means "not given")
  return map_.contains(key) && !map_.node()[key].IsNull();
}

void FieldReader::describe(const std::string& key, std::string fallback, std::string range,
                           std::string unit) {
  if (schema_)
    schema_->push_back({field(key), std::move(fallback), std::move(range), std::move(unit)});
}

double FieldReader::number(const std::string& key, double fallback, double min, double max,
                           const std::string& unit) {
  describe(key, formatNumber(fallback), "[" + formatNumber(min) + ", " + formatNumber(max) + "]",
           unit);
  const YAML::Node v = get(key);
  if (!v || v.IsNull()) return fallback;
  double value = 0.0;
  try {
    value = v.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(field(key) + " must be a number" + where(v));
  }
  if (!std::isfinite(value) || value < min || value > max)
    throw ConfigError(rangeMessage(field(key), value, min, max, unit) + where(v));
  return value;
}

int FieldReader::integer(const std::string& key, int fallback, int min, int max) {
  describe(key, std::to_string(fallback),
           "integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  const YAML::Node v = get(key);
  if (!v || v.IsNull()) return fallback;
  int value = 0;
  try {
    value = v.as<int>();
  } catch (const YAML::Exception&) {
    const std::string got = v.IsScalar() ? ", got " + abbreviated(v.Scalar()) : "";
    throw ConfigError(field(key) + " must be an integer in [" + std::to_string(min) + ", " +
                      std::to_string(max) + "]" + got + where(v));
  }
  if (value < min || value > max)
    throw ConfigError(rangeMessage(field(key), value, min, max) + where(v));
  return value;
}

bool FieldReader::flag(const std::string& key, bool fallback) {
  describe(key, fallback ? "true" : "false", "true or false");
  const YAML::Node v = get(key);
  if (!v || v.IsNull()) return fallback;
  try {
    return v.as<bool>();
  } catch (const YAML::Exception&) {
    throw ConfigError(field(key) + " must be true or false" + where(v));
  }
}

std::string FieldReader::choice(const std::string& key, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
  describe(key, fallback, "one of: " + joined(allowed));
  const YAML::Node v = get(key);
  if (!v || v.IsNull()) return fallback;
  if (!v.IsScalar())
    throw ConfigError(field(key) + " must be one of: " + joined(allowed) + where(v));
  const std::string value = v.as<std::string>();
  for (const std::string& a : allowed)
    if (a == value) return value;
  throw ConfigError(field(key) + " must be one of: " + joined(allowed) + "; got '" +
                    abbreviated(value) + "'" + where(v));
}

Vec3 FieldReader::vector3(const std::string& key, const Vec3& fallback) {
  describe(key,
           "[" + formatNumber(fallback(0)) + ", " + formatNumber(fallback(1)) + ", " +
               formatNumber(fallback(2)) + "]",
           "3 finite numbers");
  const YAML::Node v = get(key);
  if (!v || v.IsNull()) return fallback;
  if (!v.IsSequence() || v.size() != 3)
    throw ConfigError(field(key) + " must be a list of 3 numbers" + where(v));
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    try {
      out(i) = v[i].as<double>();
    } catch (const YAML::Exception&) {
      throw ConfigError(field(key) + " must be a list of 3 numbers" + where(v));
    }
    if (!std::isfinite(out(i)))
      throw ConfigError(field(key) + " must hold finite numbers" + where(v));
  }
  return out;
}

std::vector<double> FieldReader::numberList(const std::string& key, double min, double max) {
  describe(key, "", "list of numbers in [" + formatNumber(min) + ", " + formatNumber(max) + "]");
  const YAML::Node v = get(key);
  std::vector<double> out;
  if (!v || v.IsNull()) return out;
  if (!v.IsSequence()) throw ConfigError(field(key) + " must be a list of numbers" + where(v));
  for (size_t i = 0; i < v.size(); ++i) {
    double x = 0.0;
    try {
      x = v[i].as<double>();
    } catch (const YAML::Exception&) {
      throw ConfigError(field(key) + "[" + std::to_string(i) + "] must be a number in [" +
                        formatNumber(min) + ", " + formatNumber(max) + "]" + where(v));
    }
    if (!std::isfinite(x) || x < min || x > max)
      throw ConfigError(rangeMessage(field(key) + "[" + std::to_string(i) + "]", x, min, max) +
                        where(v));
    out.push_back(x);
  }
  return out;
}

FieldReader FieldReader::child(const std::string& key) {
  FieldReader c(get(key), field(key));
  c.schema_ = schema_;
  return c;
}

std::vector<std::string> FieldReader::keys() const { return map_.keys(); }

void FieldReader::rejectUnknown() const {
  if (const std::optional<YAML::Node> unknown = map_.firstUnknownKey())
    throw ConfigError("unknown field '" + field(unknown->as<std::string>()) + "'" +
                      where(*unknown) + " (allowed: " + joined(map_.knownKeys()) + ")");
}

void applyOverride(YAML::Node& root, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError("override '" + abbreviated(assignment) +
                      "' must look like section.field=value");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  if (text.find_first_not_of(" \t") == std::string::npos)
    throw ConfigError("override '" + abbreviated(assignment) + "' has an empty value");
  YAML::Node parsed;
  try {
    parsed = loadStrictYamlText(text, "override '" + path + "'");
  } catch (const YamlInputError& e) {
    throw ConfigError("override '" + abbreviated(path) +
                      "': cannot parse the value: " + e.message());
  }
  // Rebuild without source marks: they would point into the override text, not the file.
  YAML::Node value;
  if (parsed.IsSequence()) {
    for (const YAML::Node& item : parsed)
      value.push_back(item.IsScalar() ? YAML::Node(item.as<std::string>()) : item);
  } else if (parsed.IsScalar()) {
    value = YAML::Node(parsed.as<std::string>());
  } else {
    value = parsed;
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // (yaml-cpp would throw BadSubscript, quoting the whole key, for a scalar or list.)
  if (root && !root.IsNull() && !root.IsMap())
    throw ConfigError("override '" + abbreviated(assignment) +
                      "': the config is not a map of sections");
  // yaml-cpp nodes are handles: walk down with fresh handles, never reassign an existing one.
  std::vector<YAML::Node> chain{root};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (next && !next.IsNull() && !next.IsMap())
      throw ConfigError("override '" + abbreviated(assignment) + "': " + abbreviated(parts[i]) +
                        " is not a section");
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
}

}  // namespace flagella
