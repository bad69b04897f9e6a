// Whether a data set could have shown an effect at all (docs/model.md 7.6): when the calibrated
// baseline fits the data, each steady-state candidate is put in at its weakest realistic
// strength (its descriptor's typical range, low end) and the baseline parameters refitted. If
// that model fits the data about as well, the data cannot tell it from the baseline; the
// measurements that would (motor rate, quantity) come from simulating both models over a grid
// of rates, ranked by how many noise sigmas apart they predict.
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/candidates.h"
#include "flagella_identify/evaluation.h"
#include "flagella_identify/fit.h"

namespace flagella {
namespace identify {

struct PowerCheck {
  std::string candidate;
  std::vector<double> strength;  ///< the candidate's variables at their weakest typical value
  bool checked = false;          ///< false: no typical strength, or the model failed (note)
  std::string note;
  double chi_square_increase = 0.0;  ///< chi^2 with the effect (baseline refitted) - without
  double threshold = 0.0;            ///< the increase above which the data rule the effect out
  bool excluded = false;             ///< chi_square_increase > threshold
  std::vector<double> values;  ///< the model with the effect: baseline refitted, then strength
  int evaluations = 0;
};

/// A measurement that would tell the model `candidate` from the model `reference`: the
/// baseline (the power check), or another candidate that explains the data as well.
struct SuggestedMeasurement {
  std::string candidate;                  ///< "granular_yield", or a pair "a + b"
  std::string reference = "baseline";     ///< "baseline", or the rival candidate's label
  double omega_T = 0.0;                   ///< [rad/s]
  std::string output;                     ///< v, omega_h, omega_t, omega_yr, R_yr
  std::vector<ConfigOverride> overrides;  ///< the row's config fields (n_tails, ...)
  double reference_value = 0.0, candidate_value = 0.0;  ///< the two predictions (SI)
  double sigma = 0.0;                                   ///< the data's noise there (SI)
  double separation = 0.0;  ///< |candidate_value - reference_value| / sigma
};

/// A suggestion's row configuration as text: "robot.n_tails 2, ..." ("" for none).
std::string configurationText(const SuggestedMeasurement& s);

/// Suggestions at least this many sigmas apart are reported (the tool's significance level).
constexpr double kDecisiveSeparation = 3.5;
/// The suggestion grid spans the data's |omega_T| range from a quarter of its lowest rate to
/// twice its highest, in this many geometric steps.
constexpr int kSuggestionRates = 12;
/// At most this many suggestions (distinct rates) per candidate.
constexpr int kSuggestionsPerCandidate = 3;

/// The weakest realistic strength of a candidate on the robot of this baseline config (each
/// TypicalStrength's end nearer the variable's off value, in its fit coordinate; the low end
/// where the candidate gives no off value), empty if it has none.
std::vector<double> weakestTypicalStrength(const Candidate& c, const YAML::Node& baseline);

/// The power check of `candidate` against the calibrated baseline `baseline` (free parameters
/// at `baseline_values`, whose chi^2 on `all_rows` is `baseline_chi_square`). The threshold is
/// the selection's: the chi-square critical value plus the parsimony penalty for the
/// candidate's variables over `count` residuals.
PowerCheck checkPower(const Model& baseline, const std::vector<double>& baseline_values,
                      double baseline_chi_square, int count, const Candidate& candidate,
                      const Evaluator& all_rows, const FitOptions& fit);

/// The steady-state measurements (grid rates x each measured output with a noise x each row
/// configuration of the data) that separate the baseline from `check`'s model by at least
/// kDecisiveSeparation, best first, at most kSuggestionsPerCandidate distinct rates.
std::vector<SuggestedMeasurement> suggestMeasurements(const Model& baseline,
                                                      const std::vector<double>& baseline_values,
                                                      const PowerCheck& check,
                                                      const MeasuredData& data,
                                                      const EvaluatorOptions& options);

/// A fitted model and the name it goes by in the suggestions.
struct LabelledModel {
  std::string label;
  const Model* model = nullptr;
  std::vector<double> values;
};

/// The steady-state measurements of the same grid that separate `candidate` from `reference`
/// by at least kDecisiveSeparation, best first, at most kSuggestionsPerCandidate distinct
/// rates. Without a table the grid is a steady run per series, measured with the series'
/// instruments (docs/model.md 7.6): as long as its longest stretch of constant command, the
/// first quarter to settle, the speed from two positions a window T apart (sigma sqrt(2)
/// sigma_p / T), the turn rates from counted turns (sigma 2 pi sqrt(2) sigma_turns / T), over
/// the series' command range.
std::vector<SuggestedMeasurement> separatingMeasurements(const LabelledModel& reference,
                                                         const LabelledModel& candidate,
                                                         const MeasuredData& data,
                                                         const EvaluatorOptions& options);

}  // namespace identify
}  // namespace flagella
