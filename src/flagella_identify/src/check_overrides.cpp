// Checks of the config overrides carried by measured data (check_overrides.h).
#include "flagella_identify/check_overrides.h"

#include <cmath>

#include "flagella_identify/candidates.h"
#include "flagella_identify/data_error.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/core/yaml_fields.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace identify {

namespace {

/// What the fit would do to an override of `name`, or "" if it leaves it alone.
std::string fittedConflict(const std::string& name, const FittedNames& fitted) {
  for (const std::string& p : fitted.parameters)
    if (name == p)
      return "names a parameter the fit supplies (--free " + p +
             "): the fitted value would replace it. Leave it out of --free, or remove the "
             "override";
  for (const auto& [candidate, paths] : fitted.candidates)
    for (const std::string& path : paths)
      if (name == path || name.rfind(path + ".", 0) == 0)
        return "is written by the candidate effect '" + candidate +
               "' when the fit tries it. Leave the candidate out (--candidates), or remove the "
               "override";
  return "";
}

/// Throws DataError at file:line for the first override the fit would replace.
void rejectFitted(const std::vector<ConfigOverride>& overrides, const FittedNames& fitted,
                  const std::string& file, int line, const std::string& what) {
  for (const auto& [name, value] : overrides) {
    const std::string conflict = fittedConflict(name, fitted);
    if (!conflict.empty())
      throw DataError(file, line, 0, what + " '" + abbreviated(name) + "' " + conflict);
  }
}

/// Throws DataError at file:line unless `baseline` with `overrides` applied is a valid config;
/// returns that config.
SimulationConfig requireValid(const YAML::Node& baseline, const std::string& baseline_source,
                              const std::vector<ConfigOverride>& overrides, const std::string& file,
                              int line, const std::string& what) {
  YAML::Node tree = YAML::Clone(baseline);
  try {
    for (const auto& [name, value] : overrides) applyOverride(tree, name + "=" + value);
    return parseSimulationConfig(tree, baseline_source);
  } catch (const ConfigError& e) {
    throw DataError(file, line, 0, what + " refused by the config reader: " + e.what());
  }
}

/// Throws DataError at the first row that measures the flagellum's tilt when the table's robot
/// has no single flagellum whose tilt the model could predict (docs/model.md 8.4.4).
void requireTiltModelled(const SteadyStateTable& table, const SimulationConfig& config,
                         const std::string& csv) {
  if (config.robot->hasFlagellumTilt()) return;
  for (const SteadyStateRow& row : table.rows) {
    const auto tilt = row.measured.find("tilt");
    if (tilt != row.measured.end() && std::isfinite(tilt->second))
      throw DataError(csv, row.line, 0,
                      "'tilt_deg' is the tilt of a single helical flagellum against the head "
                      "axis (docs/model.md 8.4.4), and this robot has no such flagellum: only "
                      "robot.type helical predicts it");
  }
}

}  // namespace

FittedNames fittedNames(const std::vector<std::string>& free,
                        const std::vector<std::string>& candidates) {
  FittedNames names;
  names.parameters = free;
  for (const Candidate* c : candidatesNamed(candidates))
    names.candidates.emplace_back(c->name, c->writes);
  return names;
}

void checkDataOverrides(const MeasuredData& data, const YAML::Node& baseline,
                        const std::string& baseline_source, const FittedNames& fitted) {
  for (const SteadyStateTable& table : data.tables) {
    rejectFitted(table.overrides, fitted, table.source, 0, "override");
    const SimulationConfig config =
        requireValid(baseline, baseline_source, table.overrides, table.source, 0, "the overrides");
    const std::string& csv = table.csv.empty() ? table.source : table.csv;
    requireTiltModelled(table, config, csv);
    for (const SteadyStateRow& row : table.rows) {
      if (row.overrides.empty()) continue;
      rejectFitted(row.overrides, fitted, csv, row.line, "override column");
      std::vector<ConfigOverride> all = table.overrides;
      all.insert(all.end(), row.overrides.begin(), row.overrides.end());
      requireValid(baseline, baseline_source, all, csv, row.line, "the row's overrides");
    }
  }
  for (const TimeSeries& s : data.series) {
    rejectFitted(s.overrides, fitted, s.source, 0, "override");
    requireValid(baseline, baseline_source, s.overrides, s.source, 0, "the overrides");
  }
}

}  // namespace identify
}  // namespace flagella
