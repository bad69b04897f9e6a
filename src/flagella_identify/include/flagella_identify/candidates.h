// The candidate effects the selection step may add to a baseline model. Every effect of the core
// simulator's registry that declares DiscoveryHints is one (its descriptor gives the variables,
// ranges and start grid), plus one candidate that is not an effect: fabrication asymmetry, which
// changes the robot's tail fields. The physics itself lives only in flagella_sim.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "flagella_identify/data_io.h"
#include "flagella_identify/fit_parameter.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {
namespace identify {

/// The observables present in a data set (bitwise or of Observable).
unsigned observablesOf(const MeasuredData& data);

struct Candidate {
  std::string name;       ///< effect name, e.g. "granular_yield"
  std::string title;      ///< e.g. "granular yield threshold"
  std::string signature;  ///< what it does to data, in the words of the diagnosis
  unsigned needs = 0;     ///< all of these observables must be present (flagella::Observable)
  std::vector<FitParameter> variables;
  /// Start points (one value per variable) tried before the joint fit; the best one starts it.
  std::vector<std::vector<double>> starts;
  /// The variables' values at which the effect vanishes or is weakest (FittableParameter::off):
  /// `apply` leaves the effect out there, so the simpler model's optimum with these values is
  /// that model exactly, and a nested fit started there ends no worse than it.
  std::vector<double> off;
  /// Writes the effect into a robot config tree for the given variable values. The tree has
  /// the run's overrides applied already (n_tails etc.); `session_time` is the run's start.
  std::function<void(YAML::Node& config, const std::vector<double>& values, double session_time)>
      apply;
  /// The config paths `apply` writes ("effects.granular_yield" for a whole section): data may
  /// not override them while the candidate is fitted (check_overrides.h).
  std::vector<std::string> writes;
  /// Realistic strengths for hidden-effect test data, drawn in this order (names as in
  /// `variables`); fabrication asymmetry draws its own (one tail shorter, or one stiffer).
  std::vector<TypicalStrength> typical;
  /// The same on a single-flagellum robot, where they differ (empty: `typical`).
  std::vector<TypicalStrength> typical_single_flagellum;
  bool steady_table_data = true;  ///< its hidden-effect case is a table (else a time series)
  /// Why the effect cannot act on the robot of this baseline config ("": it can), e.g. a
  /// granular yield on a swimmer in a liquid; unset: it acts on every robot.
  std::function<std::string(const YAML::Node& baseline)> not_applicable;
};

/// The standard candidate list: the registry's effects with DiscoveryHints, in the registry's
/// order, then fabrication asymmetry.
const std::vector<Candidate>& standardCandidates();
const Candidate& candidateByName(const std::string& name);
/// The candidates of these names (each checked by candidateByName); all standard ones if empty.
std::vector<const Candidate*> candidatesNamed(const std::vector<std::string>& names);

/// Why a candidate cannot be identified from data with these observables ("" if it can).
std::string notIdentifiableReason(const Candidate& c, unsigned observables);
/// The robot's tail count as its type's parser reads it (defaults included): 1 for a
/// single-flagellum robot.
int tailCountOf(const YAML::Node& config);
/// Whether the robot swims on one flagellum (fewer than two tails): no tail can differ from
/// the others, and the discovery cases use the single-flagellum plan (discovery_cases.h).
bool isSingleFlagellum(const YAML::Node& config);

/// The realistic strengths of a candidate on the robot of this baseline config.
const std::vector<TypicalStrength>& typicalStrengths(const Candidate& c,
                                                     const YAML::Node& baseline);

/// Why a candidate cannot act on the robot of this baseline config ("" if it can): it is then
/// neither fitted, nor power-checked, nor suggested.
std::string notApplicableReason(const Candidate& c, const YAML::Node& baseline);

}  // namespace identify
}  // namespace flagella
