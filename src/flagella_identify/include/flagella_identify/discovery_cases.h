// The hidden-effect cases the tests and the detection benchmark draw: which effect is hidden
// (one, two, none, or one outside the candidate list), in what kind of data, at a strength
// drawn with a seed from a realistic range for the design-1 granular robot
// (config/identification/granular_design1_coarse.yaml); the table cases also run on a
// single-flagellum swimmer (config/identification/helical_shore32_coarse.yaml). The truth's
// baseline parameters are also drawn (viscosity, C_t, C_r within x0.8-1.25), so every case needs a
// calibration.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "flagella_identify/data_io.h"
#include "flagella_identify/evaluation.h"

namespace flagella {
namespace identify {

struct DiscoveryCase {
  std::string name;                 ///< e.g. "granular_yield", "null_table", "unknown_ripple"
  std::vector<std::string> hidden;  ///< candidate effects in the truth (empty: none or unknown)
  bool unknown = false;             ///< an effect outside the candidate list is hidden
  bool table = true;                ///< steady-state table (true) or time series (false)
  int tails = 0;                    ///< robot.n_tails of the data (0: the baseline config's)
  /// Strength drawn from the typical range x this (40: a lateral force that makes the robot
  /// circle on a radius well under a body length, strong enough to defeat the baseline).
  double strength_scale = 1.0;
  /// A sparse table: these motor rates [rpm] on a 2-tailed robot instead of the standard plan
  /// (7 rates x 2 and 3 tails); empty: the standard plan.
  std::vector<double> sparse_rpm;
};

/// Whether an identification's verdict is right for a case: the named set is the hidden one;
/// for a hidden effect, "cannot tell" with it among the suggested measurements' candidates is
/// also right (the data could not show it); nothing named for a null case; an unexplained
/// residual for an effect outside the list.
bool rightVerdict(const DiscoveryCase& c, const struct IdentifyResultView& r);

const std::vector<DiscoveryCase>& discoveryCases();
const DiscoveryCase& discoveryCaseByName(const std::string& name);

struct GeneratedCase {
  MeasuredData data;
  std::map<std::string, double> truth;  ///< every drawn truth value, by parameter name
  YAML::Node truth_config;              ///< the truth model's robot config (no overrides)
  /// The truth model's parameter values (baseline parameters, then each hidden effect's
  /// variables), and the same with the hidden effects at their off values.
  std::vector<double> truth_values, truth_without_hidden;
  std::string description;
};

/// Why case `c` cannot be generated for the robot of this baseline config ("" if it can): a
/// hidden effect that cannot act on it (notApplicableReason), or a plan made for the tailed
/// robots (tail counts, sparse rates) on a single-flagellum one.
std::string caseNotApplicableReason(const DiscoveryCase& c, const YAML::Node& baseline);

/// Draws the truth and the noise with `seed` and generates the data set (std::invalid_argument
/// if the case does not apply to the baseline's robot). Tables: on a robot with tails, 7 rates
/// (40-250 rpm) on 2 and 3 tails; on a single-flagellum robot, 12 rates (20-90 rpm). Time
/// series: 90 s of 120, 240 and -180 rpm on a robot with tails; on a single-flagellum robot a
/// 3-D head track of 40 s, 20 s at 40 rpm then 20 s at 80 rpm.
GeneratedCase generateCase(const DiscoveryCase& c, const YAML::Node& baseline,
                           const std::string& baseline_source, std::uint64_t seed,
                           const EvaluatorOptions& options = {});

/// How far a case's hidden effects move the truth's predictions of its own data: the sum over
/// the residuals of ((truth - truth without the hidden effects) / sigma)^2, for the training
/// and the held-out part of the identification's default split (makeSplit; small tables are
/// cross-validated instead); and what of it is left once the baseline parameters (C_t, C_r,
/// ...) are refitted on the training part to absorb what they can, to first order (a linear
/// least-squares step on their forward-difference Jacobian, log steps of 1e-3). Where the
/// unabsorbed training part is under about 10.8 (chi^2 of one parameter at p = 1e-3), no fit
/// on the training rows can establish the effect, whatever the tool does (docs/model.md 7.6).
struct HiddenSignature {
  bool defined = false;  ///< false for a case without a hidden candidate (null, unknown)
  double train_chi_square = 0.0, held_out_chi_square = 0.0;
  double train_unabsorbed = 0.0, held_out_unabsorbed = 0.0;
  int train_count = 0, held_out_count = 0;
};
HiddenSignature hiddenSignature(const DiscoveryCase& c, const GeneratedCase& g,
                                const YAML::Node& baseline, const std::string& baseline_source,
                                const EvaluatorOptions& options = {});
/// The baseline parameters the cases perturb and the tool fits.
const std::vector<std::string>& caseFreeParameters();
/// The same for the robot of this baseline config: on a single-flagellum robot the head's C_t
/// and C_r only (the viscosity does not change a rate-driven rigid swimmer's speeds).
std::vector<std::string> caseFreeParameters(const YAML::Node& baseline);

}  // namespace identify
}  // namespace flagella
