// A fitted model judged on the held-out data, and the selection score (docs/model.md 7.6).
#include <algorithm>
#include <cmath>

#include "flagella_identify/chi_square.h"
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

/// The held-out scores of a fitted outcome whose held-out evaluation succeeded: noise test,
/// share of the baseline's excess explained, and the test against `reference`.
void scoreHeldOut(ModelOutcome& out, const ModelOutcome& reference, double base_excess) {
  const Evaluation& held = out.held_out;
  out.held_out_chi_square = chiSquare(held);
  out.held_out_count = static_cast<int>(held.points.size());
  out.held_out_rms_z = std::sqrt(out.held_out_chi_square / std::max(1, out.held_out_count));
  out.noise_z = noiseZScore(out.held_out_chi_square, out.held_out_count);
  out.explained =
      base_excess > 0.0
          ? 1.0 - std::max(0.0, out.held_out_chi_square - out.held_out_count) / base_excess
          : 0.0;
  const int extra = out.extra_parameters - reference.extra_parameters;
  if (extra > 0) {
    out.improvement = reference.held_out_chi_square - out.held_out_chi_square;
    out.penalty = extra * std::log(static_cast<double>(std::max(2, out.held_out_count)));
    out.critical = chiSquareCritical(extra);
    out.significant = out.improvement - out.penalty > out.critical;
  }
}

}  // namespace

double selectionScore(const ModelOutcome& m) { return m.held_out_chi_square + m.penalty; }

const ModelOutcome* bestFitted(const std::vector<ModelOutcome>& outcomes, bool significant_only) {
  const ModelOutcome* best = nullptr;
  for (const ModelOutcome& m : outcomes)
    if (m.fitted && (m.significant || !significant_only) &&
        (!best || selectionScore(m) < selectionScore(*best)))
      best = &m;
  return best;
}

const ModelOutcome* bestSignificant(const std::vector<ModelOutcome>& outcomes) {
  return bestFitted(outcomes, true);
}

void Identification::judge(ModelOutcome& out, const ModelOutcome& reference) {
  if (folds_) {
    out.held_out = crossValidatedResiduals(out, out.evaluations);
  } else {
    out.held_out = evaluator_.evaluate(modelOf(out), valuesOf(out.parameters), Part::kHeldOut);
    out.evaluations += 1;
  }
  if (!out.held_out.ok) {
    out.fitted = false;
    out.note = "the fitted model fails on the held-out experiments: " + out.held_out.failure;
    return;
  }
  scoreAgainst(out, reference);
  say(formatted("    held-out chi^2 %.4g over %.0f residuals (RMS z %.3g)", out.held_out_chi_square,
                out.held_out_count, out.held_out_rms_z) +
      (folds_ ? formatted(", cross-validated over %.0f folds", folds_->folds.size()) : ""));
}

void Identification::scoreAgainst(ModelOutcome& out, const ModelOutcome& reference) const {
  scoreHeldOut(out, reference, baseline_excess_);
  // docs/model.md 7.6: with cross validation the fit saw every row, so an effect in the data
  // lowers it too; a cross-validated gain without that is the folds' refits, not the effect
  const double training_drop = reference.train_chi_square - out.train_chi_square;
  if (folds_ && out.significant && training_drop - out.penalty <= out.critical) {
    out.significant = false;
    say(
        formatted("    not significant: on every row its fit lowers chi^2 by only %.3g (the bar "
                  "is %.3g)",
                  training_drop, out.penalty + out.critical));
  }
}

}  // namespace identify
}  // namespace flagella
