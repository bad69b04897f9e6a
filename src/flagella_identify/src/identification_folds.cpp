// Cross validation of small tables (docs/model.md 7.6): the folds and each fold's prediction.
#include <algorithm>

#include "flagella_identify/calibration.h"
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

int rowCount(const MeasuredData& data) {
  int rows = 0;
  for (const SteadyStateTable& t : data.tables) rows += static_cast<int>(t.rows.size());
  return rows;
}

Evaluation Identification::crossValidatedResiduals(const ModelOutcome& out,
                                                   int& evaluations) const {
  Evaluation all;
  FitOptions options = fitOptionsFor(data_, options_.fit);
  options.progress = nullptr;
  options.max_iterations = std::min(options.max_iterations, kFoldIterations);
  for (size_t f = 0; f < folds_->folds.size(); ++f) {
    // docs/model.md 7.6: each fold refits from the all-rows optimum and predicts its rows
    const Evaluator fold(data_, folds_->folds[f], options_.evaluator);
    Model model = modelOf(out);
    const FitResult fit = fitModel(model, fold, options);
    evaluations += fit.evaluations;
    Evaluation held = fit.ok ? fold.evaluate(model, model.values(), Part::kHeldOut) : Evaluation{};
    evaluations += fit.ok ? 1 : 0;
    if (!fit.ok || !held.ok) {
      all.ok = false;
      all.failure = formatted("fold %.0f: ", f + 1.0) + (fit.ok ? held.failure : fit.message);
      return all;
    }
    all.points.insert(all.points.end(), held.points.begin(), held.points.end());
  }
  return all;
}

void Identification::planCrossValidation(const ModelOutcome& baseline, IdentifyResult& result) {
  const Model model = modelOf(baseline);
  std::vector<std::string> names;
  for (const FitParameter& p : model.parameters()) names.push_back(p.name);
  const FitOptions fit = fitOptionsFor(data_, options_.fit);
  RowInformation info =
      rowInformation(model, model.values(), evaluator_, fit.log_step, fit.linear_step);
  result.total_evaluations += static_cast<int>(names.size()) + 1;
  // The candidates' variables are parameters too (docs/model.md 7.6): each at its weakest
  // realistic strength (else its first start), beside the calibrated baseline.
  const unsigned observables = observablesOf(data_);
  for (const Candidate* c : candidatesNamed(options_.candidates)) {
    if (!skipReason(*c, observables).empty()) continue;
    std::vector<double> strength = weakestTypicalStrength(*c, baseline_);
    if (strength.empty() && !c->starts.empty()) strength = c->starts.front();
    if (strength.empty()) continue;
    Model with(model);
    with.addCandidate(*c);
    std::vector<double> values = model.values();
    values.insert(values.end(), strength.begin(), strength.end());
    const RowInformation more = rowInformation(with, values, evaluator_, fit.log_step,
                                               fit.linear_step, model.parameters().size());
    result.total_evaluations += static_cast<int>(strength.size()) + 1;
    for (const FitParameter& v : c->variables) names.push_back(v.name);
    for (size_t t = 0; t < info.size(); ++t)
      for (size_t r = 0; r < info[t].size(); ++r)
        info[t][r].insert(info[t][r].end(), more[t][r].begin(), more[t][r].end());
  }
  folds_ = planFolds(data_, info, names);
  result.validation_notes = folds_->notes;
  result.validation = formatted(
      "%.0f-fold cross validation (%.0f rows: fewer than %.0f, so one split would judge on "
      "too few)",
      folds_->folds.size(), rowCount(data_), kCrossValidationRows);
  if (folds_->always_training_rows > 0)
    result.validation += formatted("; %.0f row(s) always train", folds_->always_training_rows);
  say("validation: " + result.validation);
  for (const std::string& note : folds_->notes) say("  " + note);
}

int Identification::fewestTrainingRows() const {
  int fewest = rowCount(data_);
  for (const Split& fold : folds_->folds)
    fewest = std::min(fewest, rowCount(data_) - heldOutRowCount(fold));
  return fewest;
}

}  // namespace identify
}  // namespace flagella
