// The verdicts "cannot tell" (docs/model.md 7.6): the power check, and two equal explanations.
#include "flagella_identify/calibration.h"
#include "flagella_identify/chi_square.h"
#include "flagella_sim/core/units.h"
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

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
    if (!c->steady_table_data || !skipReason(*c, observables).empty()) continue;
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

}  // namespace identify
}  // namespace flagella
