// One model fitted on the training data, directly or by continuation (docs/model.md 7.6).
#include <algorithm>

#include "flagella_identify/calibration.h"
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

/// Why a fit ended, for the progress lines: the minimiser's own message.
std::string stoppedBecause(const FitResult& fit) {
  return (fit.converged ? "converged: " : "not converged: ") + fit.message;
}

}  // namespace

ModelOutcome Identification::fitModelOutcome(const std::vector<const Candidate*>& effects,
                                             const ModelOutcome& reference) {
  ModelOutcome out = fitOnTraining(effects, reference);
  if (out.fitted) judge(out, reference);
  return out;
}

ModelOutcome Identification::fitOnTraining(const std::vector<const Candidate*>& effects,
                                           const ModelOutcome& reference) {
  ModelOutcome out = fitFrom(effects, reference, nullptr);
  // docs/model.md 7.6: a baseline that ends off its map is fitted again by continuation
  if (effects.empty() && options_.continuation && !data_.series.empty() &&
      (!out.fitted || !out.warnings.empty())) {
    say("    " + (out.fitted ? out.warnings.front() : out.note) +
        "; fitting again by continuation (series summary features first)");
    out = betterOf(std::move(out), fitByContinuation(effects, reference));
  }
  return out;
}

ModelOutcome Identification::fitByContinuation(const std::vector<const Candidate*>& effects,
                                               const ModelOutcome& reference) {
  EvaluatorOptions options = options_.evaluator;
  options.series_features = true;
  const Evaluator features(data_, evaluator_.split(), options);
  return fitFrom(effects, reference, &features);
}

ModelOutcome Identification::betterOf(ModelOutcome direct, ModelOutcome continued) const {
  const bool better =
      continued.fitted && (!direct.fitted || continued.train_chi_square < direct.train_chi_square);
  ModelOutcome& kept = better ? continued : direct;
  kept.evaluations = direct.evaluations + continued.evaluations;
  say(std::string("    kept the ") + (better ? "continuation" : "direct") + " fit" +
      (kept.warnings.empty() ? "" : "; off its map: " + joined(kept.warnings, "; ")));
  return std::move(kept);
}

ModelOutcome Identification::fitFrom(const std::vector<const Candidate*>& effects,
                                     const ModelOutcome& reference, const Evaluator* features) {
  ModelOutcome out;
  Model model(baseline_, source_, options_.free);
  for (const Candidate* c : effects) {
    model.addCandidate(*c);
    out.effects.push_back(c->name);
  }
  out.label = effects.empty() ? "baseline" : joined(out.effects, " + ");
  out.continuation = features != nullptr;
  const Evaluator& first = features ? *features : evaluator_;
  const StartChoice start = bestStartValues(first, model, effects, reference, out.evaluations);
  model.setValues(start.values);
  out.starts = {start.description};
  say("  fitting " + out.label + " (" + std::to_string(model.parameters().size()) + " parameters)" +
      (features ? " on the summary features" : ""));
  FitOptions options = fitOptionsFor(data_, options_.fit);
  options.progress = fitProgress();
  if (capping_singles_ && effects.size() == 1 && options_.single_fit_max_iterations > 0)
    options.max_iterations = std::min(options.max_iterations, options_.single_fit_max_iterations);
  if (features) {
    const FitResult stage = fitModel(model, *features, options);
    out.evaluations += stage.evaluations;
    if (!stage.ok) {
      out.note = "summary features: " + stage.message;
      say("    fit failed: " + out.note);
      return out;
    }
    say(formatted("    features: %.0f iterations, chi^2 %.4g (", stage.iterations,
                  stage.chi_square) +
        stoppedBecause(stage) + "); then the samples");
  }
  const FitResult fit = fitModel(model, evaluator_, options);
  out.evaluations += fit.evaluations;
  if (!fit.ok) {
    out.note = fit.message;
    say("    fit failed: " + fit.message);
    return out;
  }
  out.fitted = true;
  out.note = fit.message;
  out.iterations = fit.iterations;
  out.converged = fit.converged;
  out.gradient_max_norm = fit.gradient_max_norm;
  out.parameters = model.parameters();
  // the baseline's parameters: a candidate's variable at its "off" bound is the effect absent
  out.warnings = offTheMap(std::vector<FitParameter>(
      out.parameters.begin(), out.parameters.begin() + model.baselineCount()));
  out.extra_parameters = static_cast<int>(model.parameters().size()) - model.baselineCount();
  out.train_chi_square = fit.chi_square;
  out.train_count = fit.residual_count;
  say(formatted("    %.0f model evaluations, %.0f iterations; training chi^2 %.4g (",
                out.evaluations, fit.iterations, out.train_chi_square) +
      stoppedBecause(fit) + ")");
  return out;
}

}  // namespace identify
}  // namespace flagella
