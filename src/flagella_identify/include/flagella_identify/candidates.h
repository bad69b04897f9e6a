// The candidate effects the selection step may add to a baseline model. Each one switches on
// a physics plug-in of the core simulator (or its fabrication-asymmetry fields) and names the
// variables a fit may change; the physics itself lives only in flagella_sim.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "flagella_identify/data_io.h"
#include "flagella_identify/fit_parameter.h"

namespace flagella {
namespace identify {

/// What kinds of measurement a candidate needs before a fit can tell it apart.
enum Observable : unsigned {
  kTranslation = 1u << 0,   ///< v, or head positions over time
  kRotation = 1u << 1,      ///< omega_h / omega_t, or counted turns
  kHeading = 1u << 2,       ///< omega_yr / R_yr, or the horizontal path of a time series
  kVertical = 1u << 3,      ///< vertical head position or orientation of a time series
  kTimeResolved = 1u << 4,  ///< a time series (events within a run)
  kSessionTime = 1u << 5,   ///< experiments spread over the session (time_s, session_time_s)
};

/// The observables present in a data set (bitwise or of Observable).
unsigned observablesOf(const MeasuredData& data);

struct Candidate {
  std::string name;       ///< effect name, e.g. "granular_yield"
  std::string title;      ///< e.g. "granular yield threshold"
  std::string signature;  ///< what it does to data, in the words of the diagnosis
  unsigned needs = 0;     ///< all of these observables must be present
  std::vector<FitParameter> variables;
  /// Start points (one value per variable) tried before the joint fit; the best one starts it.
  std::vector<std::vector<double>> starts;
  /// Writes the effect into a robot config tree for the given variable values. The tree has
  /// the run's overrides applied already (n_tails etc.); `session_time` is the run's start.
  std::function<void(YAML::Node& config, const std::vector<double>& values, double session_time)>
      apply;
};

/// The standard candidate list (issue list + README): interface lateral force, granular
/// yield, granular jamming, DC motor, centre-of-mass offset, fabrication asymmetry,
/// viscosity drift.
const std::vector<Candidate>& standardCandidates();
const Candidate& candidateByName(const std::string& name);

/// Why a candidate cannot be identified from data with these observables ("" if it can).
std::string notIdentifiableReason(const Candidate& c, unsigned observables);

}  // namespace identify
}  // namespace flagella
