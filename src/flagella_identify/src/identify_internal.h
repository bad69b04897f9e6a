// Library-internal pieces shared by the files of the discovery pipeline (docs/model.md 7.6).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flagella_identify/identify.h"

namespace flagella {
namespace identify {

// ---- start values (start_values.cpp) ----

/// The start of a fit and where it came from, in words (ModelOutcome::starts).
struct StartChoice {
  std::vector<double> values;
  std::string description;
};

/// Start values for fitting `model` (the baseline plus `effects`): the reference model's values
/// where the parameters coincide, and for each new candidate the best of its start points
/// (training chi^2) with the others fixed. Adds the model evaluations to `evaluations`.
StartChoice bestStartValues(const Evaluator& evaluator, const Model& model,
                            const std::vector<const Candidate*>& effects,
                            const ModelOutcome& reference, int& evaluations);

// ---- selection (held_out_judgement.cpp) ----

/// Selection score: held-out chi^2 plus the parsimony penalty.
double selectionScore(const ModelOutcome& m);

/// The fitted outcome (with significant_only, the fitted and significant one) with the lowest
/// score; nullptr if there is none.
const ModelOutcome* bestFitted(const std::vector<ModelOutcome>& outcomes, bool significant_only);
/// bestFitted(outcomes, true).
const ModelOutcome* bestSignificant(const std::vector<ModelOutcome>& outcomes);

// ---- the verdict in words (verdict_text.cpp) ----

/// The summary when the calibrated baseline predicts the held-out data within the noise.
std::string noDiscrepancySummary(const Diagnosis& d);

/// The verdict, the named effects and the summary for a significant baseline discrepancy,
/// given the chosen model (if any); result.gain is already set.
void decideVerdict(IdentifyResult& result, const std::optional<ModelOutcome>& chosen);

/// docs/model.md 7.6: a baseline off its map is never used silently: the summary says so.
void cautionOffTheMap(IdentifyResult& result);

// ---- the data's rows (identification_folds.cpp) ----

/// The rows of all the data's steady-state tables.
int rowCount(const MeasuredData& data);

}  // namespace identify
}  // namespace flagella
