// Sweep file reading, validation and expansion (sweep_spec.h).
#include "flagella_sweep/sweep_spec.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <regex>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::sweep {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& what) {
  throw ConfigError(file + ": " + field + ": " + what);
}

std::string scalarText(const std::string& file, const std::string& field, const YAML::Node& node) {
  if (!node.IsScalar() || node.Tag() == "~" || node.Scalar().empty())
    fail(file, field, "must be a number or a word (not a list, map or null)");
  return node.Scalar();
}

void checkField(const std::string& file, const std::string& field) {
  static const std::regex pattern("[A-Za-z_][A-Za-z0-9_]*(\\.[A-Za-z_][A-Za-z0-9_]*)+");
  if (!std::regex_match(field, pattern))
    fail(file, "sweep parameter '" + field + "'", "must be a config field section.field");
}

YAML::Node loadSingleDocument(const std::string& path) {
  const YAML::Node root = loadStrictYamlFile(path, "sweep");
  if (!root.IsMap()) throw ConfigError(path + ": must hold a map with the key 'sweep'");
  return root;
}

}  // namespace

const char* toolName(SweepTool tool) {
  switch (tool) {
    case SweepTool::Run:
      return "run";
    case SweepTool::Buckling:
      return "buckling";
    case SweepTool::Steer:
      return "steer";
  }
  return "?";
}

namespace {

// The 'sweep' map of the file's root, after checking the root's and the map's keys.
YAML::Node sweepSection(const std::string& path, const YAML::Node& root) {
  for (const auto& kv : root)
    if (kv.first.as<std::string>() != "sweep")
      fail(path, kv.first.as<std::string>(), "unknown key (the file holds one map, 'sweep')");
  const YAML::Node s = root["sweep"];
  if (!s || !s.IsMap()) fail(path, "sweep", "must be a map");
  static const std::vector<std::string> known = {"tool", "config", "args", "grid", "points"};
  for (const auto& kv : s) {
    const std::string key = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail(path, "sweep." + key, "unknown key (known: tool, config, args, grid, points)");
  }
  return s;
}

// The tool named by sweep.tool.
SweepTool readTool(const std::string& path, const YAML::Node& s) {
  if (!s["tool"]) fail(path, "sweep.tool", "missing (run, buckling or steer)");
  const std::string tool = scalarText(path, "sweep.tool", s["tool"]);
  if (tool == "run")
    return SweepTool::Run;
  else if (tool == "buckling")
    return SweepTool::Buckling;
  else if (tool == "steer")
    return SweepTool::Steer;
  else
    fail(path, "sweep.tool", "must be run, buckling or steer, got '" + tool + "'");
}

// Fills spec.parameters and spec.points from sweep.grid (every combination, first field slowest).
void readGrid(const std::string& path, const YAML::Node& grid, SweepSpec& spec) {
  if (!grid.IsMap() || grid.size() == 0)
    fail(path, "sweep.grid", "must be a map field: [values...] with at least one field");
  std::vector<std::vector<std::string>> values;
  long long count = 1;
  for (const auto& kv : grid) {
    const std::string field = kv.first.as<std::string>();
    const std::string name = "sweep.grid." + field;
    checkField(path, field);
    if (!kv.second.IsSequence() || kv.second.size() == 0)
      fail(path, name, "must be a non-empty list of values");
    spec.parameters.push_back(field);
    values.emplace_back();
    for (std::size_t i = 0; i < kv.second.size(); ++i)
      values.back().push_back(scalarText(path, name + "[" + std::to_string(i) + "]", kv.second[i]));
    count *= static_cast<long long>(values.back().size());
    if (count > kMaxPoints)
      fail(path, "sweep.grid", "expands to more than " + std::to_string(kMaxPoints) + " points");
  }
  for (long long p = 0; p < count; ++p) {  // the first field varies slowest
    PointSettings point;
    long long rest = p;
    std::vector<std::size_t> digit(values.size());
    for (std::size_t k = values.size(); k-- > 0;) {
      digit[k] = static_cast<std::size_t>(rest % values[k].size());
      rest /= static_cast<long long>(values[k].size());
    }
    for (std::size_t k = 0; k < values.size(); ++k)
      point.emplace_back(spec.parameters[k], values[k][digit[k]]);
    spec.points.push_back(std::move(point));
  }
}

// Fills spec.parameters and spec.points from the explicit list sweep.points.
void readPoints(const std::string& path, const YAML::Node& points, SweepSpec& spec) {
  if (!points.IsSequence() || points.size() == 0)
    fail(path, "sweep.points", "must be a non-empty list of maps field: value");
  if (points.size() > static_cast<std::size_t>(kMaxPoints))
    fail(path, "sweep.points", "more than " + std::to_string(kMaxPoints) + " points");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string name = "sweep.points[" + std::to_string(i) + "]";
    if (!points[i].IsMap() || points[i].size() == 0)
      fail(path, name, "must be a non-empty map field: value");
    PointSettings point;
    for (const auto& kv : points[i]) {
      const std::string field = kv.first.as<std::string>();
      checkField(path, field);
      for (const auto& [seen, value] : point)
        if (seen == field) fail(path, name + "." + field, "given twice");
      point.emplace_back(field, scalarText(path, name + "." + field, kv.second));
      if (std::find(spec.parameters.begin(), spec.parameters.end(), field) == spec.parameters.end())
        spec.parameters.push_back(field);
    }
    spec.points.push_back(std::move(point));
  }
}

// Loads every point's config so that a bad field or value fails before anything runs.
void checkPointsLoad(const std::string& path, const fs::path& config, const SweepSpec& spec) {
  for (int i = 0; i < static_cast<int>(spec.points.size()); ++i) {
    try {
      loadSimulationConfig(config.string(), pointOverrides(spec, i));
    } catch (const std::exception& e) {
      fail(path, "point " + std::to_string(i), e.what());
    }
  }
}

}  // namespace

SweepSpec loadSweepSpec(const std::string& path) {
  const YAML::Node root = loadSingleDocument(path);
  const YAML::Node s = sweepSection(path, root);
  SweepSpec spec;
  spec.file = path;
  spec.directory = fs::absolute(fs::path(path)).parent_path().lexically_normal().string();

  spec.tool = readTool(path, s);

  if (!s["config"]) fail(path, "sweep.config", "missing (the base config, relative to this file)");
  spec.config = scalarText(path, "sweep.config", s["config"]);
  const fs::path config = fs::path(spec.directory) / spec.config;
  if (!fs::is_regular_file(config))
    fail(path, "sweep.config", "no such file '" + config.lexically_normal().string() + "'");

  if (const YAML::Node args = s["args"]) {
    if (!args.IsSequence()) fail(path, "sweep.args", "must be a list of words");
    for (std::size_t i = 0; i < args.size(); ++i)
      spec.args.push_back(scalarText(path, "sweep.args[" + std::to_string(i) + "]", args[i]));
  }

  const YAML::Node grid = s["grid"], points = s["points"];
  if (static_cast<bool>(grid) == static_cast<bool>(points))
    fail(path, "sweep", "needs exactly one of 'grid' and 'points'");
  if (grid)
    readGrid(path, grid, spec);
  else
    readPoints(path, points, spec);
  // Every point's config must load: a bad field or value fails here, before anything runs.
  checkPointsLoad(path, config, spec);
  return spec;
}

std::vector<std::string> pointOverrides(const SweepSpec& spec, int index) {
  std::vector<std::string> out;
  for (const auto& [field, value] : spec.points.at(static_cast<std::size_t>(index)))
    out.push_back(field + "=" + value);
  return out;
}

}  // namespace flagella::sweep
