// The pair rule (docs/model.md 7.6): a pair is named only if it beats each effect refit alone.
#include <cmath>
#include <functional>

#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

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

ModelOutcome Identification::refitAlone(const IdentifyResult& result, const ModelOutcome& pair,
                                        size_t member) {
  const Candidate& effect = candidateByName(pair.effects[member]);
  const ModelOutcome* own = outcomeLabelled(result.candidates, effect.name);
  // docs/model.md 7.6 (the pair rule): from the pair's optimum with the other effect off, and
  // from the start the tool already has: its own first fit, taken as it is if it converged,
  // else continued from its end (from its start points if it failed)
  std::vector<std::string> where = {"the pair's optimum with " + pair.effects[1 - member] + " off"};
  std::vector<ModelOutcome> fits(2);
  std::vector<std::function<void()>> refits = {[&] {
    say("  " + effect.name + " alone from " + where[0]);
    fits[0] = fitOnTraining({&effect}, pair);
  }};
  const bool own_final = own && own->fitted && own->converged;
  if (own_final) {
    where.push_back("its first fit (converged, not fitted again)");
    fits[1] = *own;
  } else {
    const bool from_end = own && own->fitted;
    where.push_back(from_end ? "the end of its first fit" : "its start points from the baseline");
    refits.push_back([&, from_end] {
      say("  " + effect.name + " alone from " + where[1]);
      fits[1] = fitOnTraining({&effect}, from_end ? *own : result.baseline);
    });
  }
  runFits(refits);
  const int evaluations = fits[0].evaluations + (own_final ? 0 : fits[1].evaluations);
  const bool second_better =
      fits[1].fitted && (!fits[0].fitted || fits[1].train_chi_square < fits[0].train_chi_square);
  const size_t best = second_better ? 1 : 0;
  ModelOutcome kept = fits[best];
  kept.evaluations = evaluations;
  kept.starts.clear();
  for (size_t k = 0; k < fits.size(); ++k)
    kept.starts.push_back(startEnding(where[k], fits[k]) + (k == best ? " (kept)" : ""));
  if (kept.fitted && !(own_final && best == 1)) judge(kept, result.baseline);
  return kept;
}

void Identification::checkPairAgainstItsSingles(IdentifyResult& result,
                                                std::optional<ModelOutcome>& chosen) {
  // docs/model.md 7.6: no verdict may rest on a fit that stopped short of its optimum. If the
  // second effect only finished what one effect's fit left undone, that effect alone, fitted
  // again to its optimum, comes within the bar of the pair.
  const ModelOutcome pair = *chosen;
  say("before naming " + pair.label + ": each of its effects fitted again alone (never capped)");
  std::vector<ModelOutcome> refits(pair.effects.size());
  std::vector<std::function<void()>> fits;
  for (size_t member = 0; member < pair.effects.size(); ++member)
    fits.push_back([&, member] { refits[member] = refitAlone(result, pair, member); });
  runFits(fits);
  for (ModelOutcome& refit : refits) {
    result.total_evaluations += refit.evaluations;
    result.pair_refits.push_back(std::move(refit));
  }
  const std::string figures = refitFigures(result.pair_refits, result.candidates);
  const ModelOutcome* single = bestFitted(result.pair_refits, false);
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

}  // namespace identify
}  // namespace flagella
