// A model under test: the baseline robot config, the baseline fields a fit may change, and the
// candidate effects switched on. It turns a vector of fit values into the SimulationConfig of
// one experiment (a table row or a time series) and into a runnable extended config.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "flagella_identify/candidates.h"
#include "flagella_identify/fit_parameter.h"
#include "flagella_identify/measured_data.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {
namespace identify {

class Model {
 public:
  /// `baseline` is the robot config tree (read with flagella::loadConfigTree; validated here
  /// through parseSimulationConfig, errors naming `source`); `free` lists baseline config paths
  /// the fit may change (start values are read from the config, ranges span a factor
  /// `range_factor` either way).
  Model(YAML::Node baseline, std::string source, const std::vector<std::string>& free,
        double range_factor = 20.0);

  void addCandidate(const Candidate& candidate);

  const std::string& source() const { return source_; }
  const std::vector<const Candidate*>& candidates() const { return candidates_; }
  /// Baseline free parameters first, then each candidate's variables in order.
  std::vector<FitParameter>& parameters() { return parameters_; }
  const std::vector<FitParameter>& parameters() const { return parameters_; }
  std::vector<double> values() const { return valuesOf(parameters_); }
  void setValues(const std::vector<double>& values);
  /// Position of the parameter called `name` in parameters(), or -1 if the model has none.
  int indexOf(const std::string& name) const;
  int baselineCount() const { return baseline_count_; }
  /// A label: "baseline" or "baseline + granular_yield + ...".
  std::string label() const;

  /// The config of one experiment: baseline, then the experiment's overrides, then the fit
  /// values (baseline fields and candidate effects).
  SimulationConfig configFor(const std::vector<ConfigOverride>& overrides, double session_time,
                             const std::vector<double>& values) const;
  /// The extended robot config as a YAML tree (fit values applied, no experiment overrides).
  YAML::Node extendedConfig() const;

 private:
  YAML::Node treeFor(const std::vector<ConfigOverride>& overrides, double session_time,
                     const std::vector<double>& values) const;

  YAML::Node baseline_;
  std::string source_;
  std::vector<FitParameter> parameters_;
  std::vector<const Candidate*> candidates_;
  int baseline_count_ = 0;
};

/// The node at a dotted path ("effects.stokes_head.C_t") of a config tree, or a null node if
/// the path does not exist.
YAML::Node configField(const YAML::Node& root, const std::string& path);

}  // namespace identify
}  // namespace flagella
