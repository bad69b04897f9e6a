#include "flagella_control/yaml_text.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/strict_yaml.h"

namespace flagella::control {

std::string numberText(double x) {
  if (!std::isfinite(x)) return std::isnan(x) ? ".nan" : (x > 0 ? ".inf" : "-.inf");
  char buffer[64];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
}

std::string quotedText(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", u);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string commentedLine(int indent, const std::string& key_value, const std::string& comment) {
  std::string s = std::string(indent, ' ') + key_value;
  if (!comment.empty()) {
    if (s.size() < 44) s.resize(44, ' ');
    s += "  # " + comment;
  }
  return s + "\n";
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream file(path);
  if (!file) throw std::runtime_error(path + ": cannot open for writing");
  file << text;
  file.close();
  if (!file) throw std::runtime_error(path + ": write failed");
}

YAML::Node loadSingleKeyFile(const std::string& path, const std::string& key,
                             const std::string& what) {
  YAML::Node root;
  try {
    root = loadStrictYamlFile(path, what);
  } catch (const YamlInputError& e) {
    throw InputFileError(e.what());  // this package's load errors are runtime errors
  }
  if (!root.IsMap()) throw InputFileError(path + ": expected a map with key '" + key + "'");
  for (const auto& entry : root) {
    const std::string name = entry.first.as<std::string>();
    if (name != key)
      throw InputFileError(path + ": " + what + " field '" + name +
                           "' is not a known field (expected only '" + key + "')");
  }
  if (!root[key]) throw InputFileError(path + ": " + what + " field '" + key + "' is missing");
  return root[key];
}

MapReader::MapReader(const YAML::Node& node, std::string path, std::string file, std::string what)
    : map_(node, std::move(path)), file_(std::move(file)), what_(std::move(what)) {
  if (!node.IsMap()) fail(map_.path(), "must be a map");
}

void MapReader::fail(const std::string& field, const std::string& what) const {
  throw InputFileError(file_ + ": " + what_ + " field '" + field + "' " + what);
}

YAML::Node MapReader::get(const std::string& key) {
  const YAML::Node n = map_.take(key);
  if (!n) fail(field(key), "is missing");
  return n;
}

double MapReader::parseNumber(const YAML::Node& n, const std::string& name) const {
  if (!n.IsScalar()) fail(name, "must be a number");
  const std::string& text = n.Scalar();
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
    fail(name, "must be a finite number, got '" + text + "'");
  return value;
}

std::string MapReader::string(const std::string& key) {
  const YAML::Node n = get(key);
  if (!n.IsScalar()) fail(field(key), "must be a string");
  return n.Scalar();
}

void MapReader::rejectUnknown() const {
  if (const std::optional<YAML::Node> unknown = map_.firstUnknownKey())
    fail(field(unknown->as<std::string>()), "is not a known field");
}

}  // namespace flagella::control
