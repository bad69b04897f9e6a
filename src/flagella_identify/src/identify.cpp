// The discovery pipeline in order (docs/model.md 7.6): calibrate, diagnose, fit, select, decide.
#include "flagella_identify/identify.h"

#include <algorithm>

#include "flagella_identify/calibration.h"
#include "flagella_identify/check_overrides.h"
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

bool crossValidated(const MeasuredData& data, const IdentifyOptions& options) {
  return options.cross_validation && wantsCrossValidation(data);
}

/// IdentifyOptions::single_fit_max_iterations: 0 (no cap) or 1 to fit.max_iterations, never
/// clamped.
void checkSingleFitCap(const IdentifyOptions& options) {
  const int cap = options.single_fit_max_iterations;
  const int most = options.fit.max_iterations;
  if (cap == 0 || (cap >= 1 && cap <= most)) return;
  throw ConfigError(
      formatted("IdentifyOptions::single_fit_max_iterations must be 0 (no cap) or in [1, %.0f] "
                "(fit.max_iterations), got %.0f",
                most, cap));
}

}  // namespace

Identification::Identification(MeasuredData data, YAML::Node baseline, std::string baseline_source,
                               IdentifyOptions options)
    : data_(std::move(data)),
      baseline_(YAML::Clone(baseline)),
      source_(std::move(baseline_source)),
      options_(std::move(options)),
      evaluator_(data_,
                 crossValidated(data_, options_) ? trainingOnlySplit(data_) : makeSplit(data_),
                 options_.evaluator) {
  checkSingleFitCap(options_);
  checkDataOverrides(data_, baseline_, source_, fittedNames(options_.free, options_.candidates));
}

Split Identification::heldOutRows() const {
  return folds_ ? heldOutInSomeFold(data_, *folds_) : evaluator_.split();
}

Model Identification::modelOf(const ModelOutcome& outcome) const {
  Model model(baseline_, source_, options_.free);
  for (const std::string& name : outcome.effects) model.addCandidate(candidateByName(name));
  if (!outcome.parameters.empty()) model.parameters() = outcome.parameters;
  return model;
}

IdentifyResult Identification::run() {
  IdentifyResult result;
  const bool cross_validate = crossValidated(data_, options_);
  say("calibrating the baseline (" + source_ + ") on " +
      (cross_validate ? "every row (small table: cross validation follows)"
                      : "the training split"));
  ModelOutcome none;
  result.baseline = fitOnTraining({}, none);
  if (!result.baseline.fitted)
    throw std::runtime_error("the baseline model could not be calibrated: " + result.baseline.note);
  if (cross_validate) {
    planCrossValidation(result.baseline, result);
    if (folds_->folds.empty()) {
      result.total_evaluations += result.baseline.evaluations;
      result.verdict = Verdict::kCannotTell;
      result.summary =
          "Cannot tell from these data: every row alone constrains a baseline parameter, so no "
          "row can be held out to test the model. Measure more rows (other motor rates).";
      return result;
    }
  } else {
    result.validation = formatted("held-out split (%.0f of %.0f table rows",
                                  heldOutRowCount(evaluator_.split()), rowCount(data_)) +
                        (data_.series.empty() ? ")" : "; the last 40 % of each series)");
  }
  judge(result.baseline, none);
  result.total_evaluations += result.baseline.evaluations;
  if (!result.baseline.fitted)
    throw std::runtime_error("the calibrated baseline cannot be judged: " + result.baseline.note);

  result.baseline_diagnosis = diagnose(result.baseline.held_out, data_);
  const Diagnosis& d = result.baseline_diagnosis;
  baseline_excess_ = std::max(0.0, d.chi_square - d.count);
  say(formatted("diagnosis: held-out RMS z %.3g, noise test z = %.2f (significant above %.1f)",
                d.rms_z, d.noise_z, kSignificanceZ));
  for (const Signature& s : d.signatures) say("  signature: " + s.kind + " - " + s.text);
  if (!d.significant) {
    if (cannotTell(result)) return result;
    result.verdict = Verdict::kNoDiscrepancy;
    result.summary = noDiscrepancySummary(d);
    cautionOffTheMap(result);
    std::vector<std::string> excluded;
    for (const PowerCheck& p : result.power)
      if (p.excluded) excluded.push_back(p.candidate);
    if (!excluded.empty())
      result.summary += " These data would have shown " + joined(excluded, ", ") +
                        " at the weakest realistic strength (power check).";
    return result;
  }

  // ---- every identifiable candidate, fitted together with the baseline parameters ----
  fitCandidates(result);
  std::optional<ModelOutcome> chosen;
  if (const ModelOutcome* best = bestSignificant(result.candidates)) chosen = *best;
  tryPairs(result, chosen);

  if (chosen) {
    result.chosen = chosen;
    result.chosen_diagnosis = diagnose(chosen->held_out, data_);
    result.gain = 1.0 - chosen->held_out_rms_z / std::max(1e-300, d.rms_z);
  }
  decideVerdict(result, chosen);
  if (!result.pair_check.empty()) result.summary += " Pair check: " + result.pair_check + ".";
  if (result.chosen && !result.chosen->converged)
    result.summary += formatted(
        " Caution: the fit of the chosen model stopped after %.0f iterations without meeting its "
        "convergence test (largest gradient component %.3g): its figures may be short of its "
        "optimum.",
        result.chosen->iterations, result.chosen->gradient_max_norm);
  if (result.verdict == Verdict::kNamedCause)
    if (const ModelOutcome* rival = closestRival(result, *result.chosen))
      cannotTellBetween(result, *rival);
  cautionOffTheMap(result);
  result.fits_at_once = most_fits_at_once_;
  say("verdict: " + verdictText(result.verdict) +
      (result.named.empty() ? "" : " (" + joined(result.named, " + ") + ")"));
  return result;
}

}  // namespace identify
}  // namespace flagella
