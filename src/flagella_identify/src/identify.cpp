#include "flagella_identify/identify.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "flagella_identify/calibration.h"
#include "flagella_identify/check_overrides.h"
#include "flagella_sim/core/units.h"
#include "text_format.h"

namespace flagella {
namespace identify {

std::string verdictText(Verdict v) {
  switch (v) {
    case Verdict::kNoDiscrepancy:
      return "no significant discrepancy";
    case Verdict::kNamedCause:
      return "named cause";
    case Verdict::kUnexplained:
      return "unexplained residual";
    case Verdict::kCannotTell:
      return "cannot tell from these data";
  }
  return "?";
}

double chiSquareCritical(int k) {
  // chi-square quantiles at p = 1e-3
  static const double table[] = {10.83, 13.82, 16.27, 18.47, 20.52, 22.46};
  return table[std::clamp(k, 1, 6) - 1];
}

namespace {

/// The start of a fit and where it came from, in words (ModelOutcome::starts).
struct StartChoice {
  std::vector<double> values;
  std::string description;
};

/// Where a fit inheriting `reference`'s values starts from, in words.
std::string referenceStartText(const ModelOutcome& reference) {
  return reference.label.empty() ? "the config's values" : "the " + reference.label + " optimum";
}

/// Start values for fitting `model` (the baseline plus `effects`): the reference model's values
/// where the parameters coincide, and for each new candidate the best of its start points
/// (training chi^2) with the others fixed. Adds the model evaluations to `evaluations`.
StartChoice bestStartValues(const Evaluator& evaluator, const Model& model,
                            const std::vector<const Candidate*>& effects,
                            const ModelOutcome& reference, int& evaluations) {
  std::string description = "from " + referenceStartText(reference);
  // Start from the reference model's values where the parameters coincide.
  const std::vector<double> config_values = model.values();
  std::vector<double> values = config_values;
  for (const FitParameter& p : reference.parameters)
    if (const int i = model.indexOf(p.name); i >= 0) values[static_cast<size_t>(i)] = p.value;
  // Try each new candidate's start points with the others fixed; keep the best. Each start is
  // tried with the baseline parameters at the reference's values and at the config's: the
  // reference may have absorbed the effect (e.g. a stiffer head drag for a granular resistance),
  // and a fit started there stays in that basin.
  size_t offset = model.baselineCount();
  for (const Candidate* c : effects) {
    const bool inherited = std::any_of(reference.effects.begin(), reference.effects.end(),
                                       [&](const std::string& n) { return n == c->name; });
    if (!inherited && !c->starts.empty()) {
      std::vector<double> config_base = values;
      std::copy(config_values.begin(), config_values.begin() + model.baselineCount(),
                config_base.begin());
      // First the reference's optimum with the new effect off: the nested fit then starts no
      // worse than the reference, and the fit never ends above its start (fit.h).
      std::vector<std::vector<double>> trials;
      if (!c->off.empty()) {
        std::vector<double> v = values;
        std::copy(c->off.begin(), c->off.end(), v.begin() + offset);
        trials.push_back(v);
      }
      for (const std::vector<double>* base : {&values, &config_base})
        for (const std::vector<double>& start : c->starts) {
          std::vector<double> v = *base;
          std::copy(start.begin(), start.end(), v.begin() + offset);
          trials.push_back(v);
        }
      const std::vector<Evaluation> evals = evaluator.evaluateMany(model, trials, Part::kTrain);
      evaluations += static_cast<int>(trials.size());
      description += formatted("; best of %.0f starts for ", trials.size()) + c->name + " (" +
                     (c->off.empty() ? "" : "off, ") +
                     "its start points at the reference's and the config's baseline values)";
      double best = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < trials.size(); ++k)
        if (evals[k].ok && chiSquare(evals[k]) < best) {
          best = chiSquare(evals[k]);
          values = trials[k];
        }
    }
    offset += c->variables.size();
  }
  return {values, description};
}

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

/// Selection score: held-out chi^2 plus the parsimony penalty.
double selectionScore(const ModelOutcome& m) { return m.held_out_chi_square + m.penalty; }

/// The fitted, significant outcome with the lowest score; nullptr if there is none.
const ModelOutcome* bestSignificant(const std::vector<ModelOutcome>& outcomes) {
  const ModelOutcome* best = nullptr;
  for (const ModelOutcome& m : outcomes)
    if (m.fitted && m.significant && (!best || selectionScore(m) < selectionScore(*best)))
      best = &m;
  return best;
}

/// The summary when the calibrated baseline predicts the held-out data within the noise.
std::string noDiscrepancySummary(const Diagnosis& d) {
  return formatted(
      "No significant discrepancy: the calibrated baseline predicts the held-out data within "
      "the measurement noise (RMS z %.2f over %.0f residuals, noise test z = %.2f < %.1f). No "
      "effect is named.",
      d.rms_z, d.count, d.noise_z, kSignificanceZ);
}

/// "kind in output; ..." of the diagnosis' signatures, or "no simple signature".
std::string signatureList(const Diagnosis& d) {
  std::string signatures;
  for (const Signature& s : d.signatures)
    signatures += (signatures.empty() ? "" : "; ") + s.kind + " in " + s.output;
  if (signatures.empty()) signatures = "no simple signature";
  return signatures;
}

/// The verdict, the named effects and the summary for a significant baseline discrepancy,
/// given the chosen model (if any); result.gain is already set.
void decideVerdict(IdentifyResult& result, const std::optional<ModelOutcome>& chosen) {
  const Diagnosis& d = result.baseline_diagnosis;
  const std::string signatures = signatureList(d);
  if (chosen && chosen->explained >= kExplainedShare) {
    result.verdict = Verdict::kNamedCause;
    result.named = chosen->effects;
    result.summary = "Named cause: " + joined(chosen->effects, " + ") +
                     formatted(
                         ". The calibrated baseline misses the held-out data (RMS z %.2f, noise "
                         "test z = %.1f; ",
                         d.rms_z, d.noise_z);
    result.summary += signatures +
                      formatted(
                          "). With the effect the held-out RMS z is %.2f (noise test "
                          "z = %.2f); it removes %.1f %% of the baseline's excess "
                          "over the noise",
                          chosen->held_out_rms_z, chosen->noise_z, 100.0 * chosen->explained) +
                      formatted("; the held-out chi^2 drops by %.1f", chosen->improvement) +
                      formatted(
                          ", more than the parsimony penalty %.1f plus the p = 0.001 critical "
                          "value %.1f. Held-out gain %.0f %%.",
                          chosen->penalty, chosen->critical, 100.0 * result.gain);
  } else {
    result.verdict = Verdict::kUnexplained;
    result.summary = formatted(
                         "Unexplained residual: the calibrated baseline misses the held-out data "
                         "(RMS z %.2f, noise test z = %.1f) with signature: ",
                         d.rms_z, d.noise_z) +
                     signatures + ". ";
    if (chosen)
      result.summary +=
          formatted("The best candidate model (" + chosen->label +
                        ") reduces the held-out RMS z to %.2f but removes only %.0f %% of "
                        "the excess over the noise (noise test z = %.1f), so no cause is "
                        "named.",
                    chosen->held_out_rms_z, 100.0 * chosen->explained, chosen->noise_z);
    else
      result.summary +=
          "No candidate effect improves the held-out error significantly, so no "
          "cause is named.";
  }
}

}  // namespace

namespace {

bool crossValidated(const MeasuredData& data, const IdentifyOptions& options) {
  return options.cross_validation && wantsCrossValidation(data);
}

int rowCount(const MeasuredData& data) {
  int rows = 0;
  for (const SteadyStateTable& t : data.tables) rows += static_cast<int>(t.rows.size());
  return rows;
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

/// docs/model.md 7.6: a baseline off its map is never used silently: the summary says so.
void cautionOffTheMap(IdentifyResult& result) {
  const ModelOutcome& b = result.baseline;
  if (b.warnings.empty()) return;
  result.summary +=
      " Caution: the calibrated baseline ended off its map (" + joined(b.warnings, "; ") + ")" +
      (b.continuation ? ", also when fitted through the series' summary features first" : "") +
      ": its figures are those of a model at the edge of its range, not a "
      "calibration of the robot.";
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

void Identification::say(const std::string& line) const {
  if (options_.progress) options_.progress(line);
}

Model Identification::modelOf(const ModelOutcome& outcome) const {
  Model model(baseline_, source_, options_.free);
  for (const std::string& name : outcome.effects) model.addCandidate(candidateByName(name));
  if (!outcome.parameters.empty()) model.parameters() = outcome.parameters;
  return model;
}

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
    say(formatted("    features: %.0f iterations, chi^2 %.4g; then the samples", stage.iterations,
                  stage.chi_square));
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
  say(formatted("    %.0f model evaluations, %.0f iterations; training chi^2 %.4g", out.evaluations,
                fit.iterations, out.train_chi_square));
  return out;
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
    if (!notIdentifiableReason(*c, observables).empty()) continue;
    std::vector<double> strength = weakestTypicalStrength(*c);
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

void Identification::fitCandidates(IdentifyResult& result) {
  const unsigned observables = observablesOf(data_);
  for (const Candidate* c : candidatesNamed(options_.candidates)) {
    const std::string reason = notIdentifiableReason(*c, observables);
    if (!reason.empty()) {
      ModelOutcome skipped;
      skipped.label = c->name;
      skipped.effects = {c->name};
      skipped.note = "not identifiable from these data: " + reason;
      result.candidates.push_back(skipped);
      say("candidate " + c->name + ": skipped (" + reason + ")");
      continue;
    }
    say("candidate " + c->name + ": " + c->title);
    capping_singles_ = true;
    result.candidates.push_back(fitModelOutcome({c}, result.baseline));
    capping_singles_ = false;
    result.total_evaluations += result.candidates.back().evaluations;
  }
  // docs/model.md 7.6: a baseline off its map may have dragged the candidates fitted from it off
  // too: unless one of them leaves a held-out residual within the noise, each again by
  // continuation.
  const ModelOutcome& base = result.baseline;
  const bool explained =
      std::any_of(result.candidates.begin(), result.candidates.end(),
                  [](const ModelOutcome& m) { return m.fitted && m.noise_z <= kSignificanceZ; });
  if (!options_.continuation || data_.series.empty() || base.warnings.empty() || explained) return;
  say("the baseline ended off its map and no candidate fitted from it leaves a residual within "
      "the noise: each candidate again by continuation");
  for (ModelOutcome& m : result.candidates) {
    if (m.note.rfind("not identifiable", 0) == 0) continue;
    std::vector<const Candidate*> effects;
    for (const std::string& name : m.effects) effects.push_back(&candidateByName(name));
    say("candidate " + m.label + " by continuation");
    ModelOutcome again = fitByContinuation(effects, base);
    result.total_evaluations += again.evaluations;
    if (again.fitted) judge(again, base);
    m = betterOf(std::move(m), std::move(again));
  }
}

int Identification::fewestTrainingRows() const {
  int fewest = rowCount(data_);
  for (const Split& fold : folds_->folds)
    fewest = std::min(fewest, rowCount(data_) - heldOutRowCount(fold));
  return fewest;
}

void Identification::tryPairs(IdentifyResult& result, std::optional<ModelOutcome>& chosen) {
  // One effect not enough: add a second one to the best and keep it if it is significant. Only
  // a first effect that explains a sizeable share can mask a second one; when the best single
  // effect explains little, a second effect would have shown on its own.
  bool pairable = chosen && chosen->noise_z > kSignificanceZ && options_.max_effects >= 2;
  // docs/model.md 7.6: a second effect only once the first is fitted at its best: with time
  // series, the best single effect is fitted again by continuation first
  if (pairable && chosen->explained >= kPairingShare && options_.continuation &&
      !data_.series.empty() && !chosen->continuation) {
    say("the best single effect (" + chosen->label +
        ") leaves a significant residual: fitted again by continuation before pairing");
    std::vector<const Candidate*> effects;
    for (const std::string& name : chosen->effects) effects.push_back(&candidateByName(name));
    ModelOutcome again = fitByContinuation(effects, result.baseline);
    result.total_evaluations += again.evaluations;
    if (again.fitted) judge(again, result.baseline);
    if (again.fitted && again.significant) {
      ModelOutcome kept = betterOf(*chosen, std::move(again));
      for (ModelOutcome& m : result.candidates)
        if (m.label == kept.label) m = kept;
      chosen = kept;
    }
    pairable = chosen->noise_z > kSignificanceZ;
  }
  if (pairable && chosen->explained < kPairingShare) {
    say("the best single effect (" + chosen->label +
        formatted(") explains only %.1f %% of the excess (< %.0f %%); no pairs tried",
                  100.0 * chosen->explained, 100.0 * kPairingShare));
  } else if (pairable) {
    say(formatted("the best single effect explains %.1f %% of the excess and leaves a significant "
                  "residual; trying pairs with ",
                  100.0 * chosen->explained) +
        chosen->label);
    const ModelOutcome first = *chosen;
    for (const ModelOutcome& m : result.candidates) {
      // every other fitted candidate: a second effect can be masked by the first one's larger
      // discrepancy, so that on its own it does not even lower the held-out error
      if (!m.fitted || m.label == first.label) continue;
      std::vector<const Candidate*> pair{&candidateByName(first.effects[0]),
                                         &candidateByName(m.effects[0])};
      // docs/model.md 7.6: with cross validation, no model with more parameters than a fold
      // trains rows (each row is one motor rate)
      const size_t parameters = first.parameters.size() + pair[1]->variables.size();
      if (folds_ && static_cast<int>(parameters) > fewestTrainingRows()) {
        say("  " + first.label + " + " + m.label +
            formatted(" not tried: %.0f parameters, more than the %.0f rows a fold trains on",
                      parameters, fewestTrainingRows()));
        continue;
      }
      ModelOutcome combined = fitModelOutcome(pair, first);
      result.total_evaluations += combined.evaluations;
      result.combinations.push_back(combined);
    }
    if (const ModelOutcome* best_pair = bestSignificant(result.combinations)) {
      chosen = *best_pair;
      if (options_.pair_rule) checkPairAgainstItsSingles(result, chosen);
    }
  }
}

namespace {

/// How one start of a refit ended, in words (ModelOutcome::starts).
std::string startEnding(const std::string& where, const ModelOutcome& fit) {
  if (!fit.fitted) return "from " + where + ": not fitted (" + fit.note + ")";
  return "from " + where +
         formatted(": training chi^2 %.6g, %.0f iterations, ", fit.train_chi_square,
                   fit.iterations) +
         (fit.converged ? "converged" : "not converged") +
         (std::isfinite(fit.gradient_max_norm)
              ? formatted(" (largest gradient component %.3g)", fit.gradient_max_norm)
              : std::string());
}

/// The outcome labelled `label` in `outcomes`, or nullptr.
const ModelOutcome* outcomeLabelled(const std::vector<ModelOutcome>& outcomes,
                                    const std::string& label) {
  for (const ModelOutcome& m : outcomes)
    if (m.label == label) return &m;
  return nullptr;
}

/// The fitted outcome of lowest selection score; nullptr if none is fitted.
const ModelOutcome* bestFitted(const std::vector<ModelOutcome>& outcomes) {
  const ModelOutcome* best = nullptr;
  for (const ModelOutcome& m : outcomes)
    if (m.fitted && (!best || selectionScore(m) < selectionScore(*best))) best = &m;
  return best;
}

/// "dc_motor held-out chi^2 14.6 (first fit 2781)" for each refit, joined by commas.
std::string refitFigures(const std::vector<ModelOutcome>& refits,
                         const std::vector<ModelOutcome>& candidates) {
  std::vector<std::string> parts;
  for (const ModelOutcome& m : refits) {
    const ModelOutcome* first = outcomeLabelled(candidates, m.label);
    const std::string before =
        first && first->fitted ? formatted(" (first fit %.4g)", first->held_out_chi_square) : "";
    parts.push_back(m.label +
                    (m.fitted ? formatted(" held-out chi^2 %.4g", m.held_out_chi_square)
                              : " not fitted (" + m.note + ")") +
                    before);
  }
  return joined(parts, ", ");
}

}  // namespace

ModelOutcome Identification::refitAlone(IdentifyResult& result, const ModelOutcome& pair,
                                        size_t member) {
  const Candidate& effect = candidateByName(pair.effects[member]);
  const ModelOutcome* own = outcomeLabelled(result.candidates, effect.name);
  // docs/model.md 7.6 (the pair rule): from the pair's optimum with the other effect off, and
  // from the start the tool already has: its own first fit, taken as it is if it converged,
  // else continued from its end (from its start points if it failed)
  std::vector<std::string> where = {"the pair's optimum with " + pair.effects[1 - member] + " off"};
  say("  " + effect.name + " alone from " + where[0]);
  std::vector<ModelOutcome> fits = {fitOnTraining({&effect}, pair)};
  int evaluations = fits[0].evaluations;
  const bool own_final = own && own->fitted && own->converged;
  if (own_final) {
    where.push_back("its first fit (converged, not fitted again)");
    fits.push_back(*own);
  } else {
    const bool from_end = own && own->fitted;
    where.push_back(from_end ? "the end of its first fit" : "its start points from the baseline");
    say("  " + effect.name + " alone from " + where[1]);
    fits.push_back(fitOnTraining({&effect}, from_end ? *own : result.baseline));
    evaluations += fits[1].evaluations;
  }
  const bool second_better =
      fits[1].fitted && (!fits[0].fitted || fits[1].train_chi_square < fits[0].train_chi_square);
  const size_t best = second_better ? 1 : 0;
  ModelOutcome kept = fits[best];
  kept.evaluations = evaluations;
  kept.starts.clear();
  for (size_t k = 0; k < fits.size(); ++k)
    kept.starts.push_back(startEnding(where[k], fits[k]) + (k == best ? " (kept)" : ""));
  if (kept.fitted && !(own_final && best == 1)) judge(kept, result.baseline);
  result.total_evaluations += kept.evaluations;
  return kept;
}

void Identification::checkPairAgainstItsSingles(IdentifyResult& result,
                                                std::optional<ModelOutcome>& chosen) {
  // docs/model.md 7.6: no verdict may rest on a fit that stopped short of its optimum. If the
  // second effect only finished what one effect's fit left undone, that effect alone, fitted
  // again to its optimum, comes within the bar of the pair.
  const ModelOutcome pair = *chosen;
  say("before naming " + pair.label + ": each of its effects fitted again alone (never capped)");
  for (size_t member = 0; member < pair.effects.size(); ++member)
    result.pair_refits.push_back(refitAlone(result, pair, member));
  const std::string figures = refitFigures(result.pair_refits, result.candidates);
  const ModelOutcome* single = bestFitted(result.pair_refits);
  if (!single) {
    result.pair_check = "neither effect alone could be fitted again (" + figures +
                        "); the pair stands on fits that may be short of their optimum";
    say("  " + result.pair_check);
    return;
  }
  // The pair against the better refit single, as judge() tests any nested model: its held-out
  // gain beyond the parsimony penalty and the critical value of the other effect's parameters
  // (and, with cross validation, its drop of the training chi^2 too).
  ModelOutcome against = pair;
  scoreAgainst(against, *single);
  const double bar = against.penalty + against.critical;
  result.pair_check =
      "each effect fitted again alone: " + figures + "; against the better, " + single->label +
      formatted(", the pair (held-out chi^2 %.4g) gains %.3g on it and ", pair.held_out_chi_square,
                against.improvement) +
      formatted(against.significant ? "clears the bar %.3g" : "does not clear the bar %.3g", bar) +
      (folds_ ? " (held-out and training chi^2)" : "") +
      (against.significant ? ": named"
                           : ": the pair is not named, the single effects are judged again");
  say("  " + result.pair_check);
  if (against.significant) return;
  const ModelOutcome fallback = *single;
  for (const ModelOutcome& refit : result.pair_refits)
    for (ModelOutcome& m : result.candidates)
      if (refit.fitted && m.label == refit.label &&
          (!m.fitted || refit.train_chi_square < m.train_chi_square))
        m = refit;
  const ModelOutcome* best = bestSignificant(result.candidates);
  chosen = best ? *best : fallback;
}

namespace {

/// One suggested measurement in words, in display units.
std::string suggestionText(const SuggestedMeasurement& s) {
  const auto [unit, factor] = displayUnit(s.output);
  const std::string where = configurationText(s);
  const std::string reference = s.reference == "baseline" ? "the baseline" : "with " + s.reference;
  return "measure " + s.output + formatted(" at %.4g rpm", s.omega_T * units::kRpmPerRadPerSec) +
         (where.empty() ? "" : " (" + where + ")") + ": " + reference +
         formatted(" predicts %.4g ", s.reference_value * factor) + unit + ", with " + s.candidate +
         formatted(" %.4g ", s.candidate_value * factor) + unit +
         formatted(", noise %.3g ", s.sigma * factor) + unit +
         formatted(" (%.1f sigma apart)", s.separation);
}

/// "To decide: ..." of the suggestions.
std::string decidingSteps(const std::vector<SuggestedMeasurement>& suggestions) {
  std::vector<std::string> steps;
  for (const SuggestedMeasurement& s : suggestions) steps.push_back(suggestionText(s));
  return "To decide: " + joined(steps, "; ") + ".";
}

}  // namespace

bool Identification::cannotTell(IdentifyResult& result) {
  if (data_.tables.empty() || !options_.power_check) return false;
  const unsigned observables = observablesOf(data_);
  // The power of the training rows (every row with cross validation), against the baseline
  // calibrated on them: a conservative figure for a split, at no extra baseline fit.
  const FitOptions fit = fitOptionsFor(data_, options_.fit);
  const Model base = modelOf(result.baseline);
  const double base_chi = result.baseline.train_chi_square;
  const int count = result.baseline.train_count;
  say("power of the data against each steady-state candidate at its weakest realistic strength");
  std::vector<std::string> blind;
  for (const Candidate* c : candidatesNamed(options_.candidates)) {
    if (!c->steady_table_data || !notIdentifiableReason(*c, observables).empty()) continue;
    const PowerCheck check = checkPower(base, base.values(), base_chi, count, *c, evaluator_, fit);
    result.total_evaluations += check.evaluations;
    result.power.push_back(check);
    if (!check.checked) {
      say("  " + c->name + ": not checked (" + check.note + ")");
      continue;
    }
    say("  " + c->name +
        formatted(": chi^2 +%.3g with the effect (rules it out above %.3g): ",
                  check.chi_square_increase, check.threshold) +
        (check.excluded ? "excluded" : "not excluded"));
    if (check.excluded) continue;
    const std::vector<SuggestedMeasurement> s =
        suggestMeasurements(base, base.values(), check, data_, options_.evaluator);
    result.total_evaluations += 2;
    if (s.empty()) {
      say("    no steady measurement of the grid would show it either");
      continue;
    }
    blind.push_back(c->name);
    result.suggestions.insert(result.suggestions.end(), s.begin(), s.end());
  }
  if (blind.empty()) return false;
  const Diagnosis& d = result.baseline_diagnosis;
  result.verdict = Verdict::kCannotTell;
  result.summary =
      formatted(
          "Cannot tell from these data: the calibrated baseline predicts them within the noise "
          "(RMS z %.2f over %.0f residuals, noise test z = %.2f), but these data could not have "
          "shown ",
          d.rms_z, d.count, d.noise_z) +
      joined(blind, " or ") +
      " at its weakest realistic strength either (the baseline with the effect fits them as "
      "well, baseline parameters refitted). No effect is named, and none is ruled out. " +
      decidingSteps(result.suggestions);
  return true;
}

const ModelOutcome* closestRival(const IdentifyResult& result, const ModelOutcome& chosen) {
  // docs/model.md 7.6: the one-parameter critical value at the tool's significance level
  const double bar = chiSquareCritical(1);
  const ModelOutcome* rival = nullptr;
  for (const std::vector<ModelOutcome>* list : {&result.candidates, &result.combinations})
    for (const ModelOutcome& m : *list) {
      if (!m.fitted || !m.significant || m.label == chosen.label ||
          m.effects.size() != chosen.effects.size() || m.explained < kExplainedShare ||
          selectionScore(m) - selectionScore(chosen) >= bar)
        continue;
      if (!rival || selectionScore(m) < selectionScore(*rival)) rival = &m;
    }
  return rival;
}

void Identification::cannotTellBetween(IdentifyResult& result, const ModelOutcome& rival) {
  const ModelOutcome& chosen = *result.chosen;
  const Model first = modelOf(chosen), second = modelOf(rival);
  result.suggestions =
      separatingMeasurements({chosen.label, &first, first.values()},
                             {rival.label, &second, second.values()}, data_, options_.evaluator);
  result.total_evaluations += 2;
  const Diagnosis& d = result.baseline_diagnosis;
  result.verdict = Verdict::kCannotTell;
  result.named.clear();
  result.summary =
      "Cannot tell between " + chosen.label + " and " + rival.label +
      formatted(
          " from these data: the calibrated baseline misses the held-out data (RMS z %.2f, "
          "noise test z = %.1f), and either effect explains it: held-out RMS z %.2f and %.2f, ",
          d.rms_z, d.noise_z, chosen.held_out_rms_z, rival.held_out_rms_z) +
      formatted(
          "%.0f %% and %.0f %% of the excess removed; their scores (held-out chi^2 plus the "
          "parsimony penalty) differ by %.2f, less than the p = 0.001 critical value %.1f for "
          "one parameter. Neither is named. ",
          100.0 * chosen.explained, 100.0 * rival.explained,
          selectionScore(rival) - selectionScore(chosen), chiSquareCritical(1));
  if (!result.suggestions.empty())
    result.summary += decidingSteps(result.suggestions);
  else
    result.summary += formatted(
        "No steady measurement of the grid (%.0f rates, each configuration and output the data "
        "measure, with their noise) separates them by %.1f sigma either.",
        kSuggestionRates, kDecisiveSeparation);
  say("verdict: cannot tell between " + chosen.label + " and " + rival.label);
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
  say("verdict: " + verdictText(result.verdict) +
      (result.named.empty() ? "" : " (" + joined(result.named, " + ") + ")"));
  return result;
}

}  // namespace identify
}  // namespace flagella
