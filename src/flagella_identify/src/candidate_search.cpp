// Every candidate effect fitted alone, then paired with the best one (docs/model.md 7.6).
#include <algorithm>
#include <functional>
#include <optional>

#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

std::string Identification::skipReason(const Candidate& c, unsigned observables) const {
  const std::string robot = notApplicableReason(c, baseline_);
  if (!robot.empty()) return "does not apply to this robot: " + robot;
  const std::string data = notIdentifiableReason(c, observables);
  return data.empty() ? "" : "not identifiable from these data: " + data;
}

void Identification::fitCandidates(IdentifyResult& result) {
  const unsigned observables = observablesOf(data_);
  const std::vector<const Candidate*> named = candidatesNamed(options_.candidates);
  std::vector<ModelOutcome> outcomes(named.size());
  std::vector<std::function<void()>> fits;
  for (size_t k = 0; k < named.size(); ++k)
    fits.push_back([&, k] {
      const Candidate& c = *named[k];
      const std::string reason = skipReason(c, observables);
      if (!reason.empty()) {
        outcomes[k].label = c.name;
        outcomes[k].effects = {c.name};
        outcomes[k].skipped = true;
        outcomes[k].note = reason;
        say("candidate " + c.name + ": skipped (" + reason + ")");
        return;
      }
      say("candidate " + c.name + ": " + c.title);
      outcomes[k] = fitModelOutcome({&c}, result.baseline);
    });
  capping_singles_ = true;
  runFits(fits);
  capping_singles_ = false;
  for (ModelOutcome& m : outcomes) {
    result.total_evaluations += m.evaluations;
    result.candidates.push_back(std::move(m));
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
  std::vector<int> again_evaluations(result.candidates.size(), 0);
  fits.clear();
  for (size_t k = 0; k < result.candidates.size(); ++k) {
    if (result.candidates[k].skipped) continue;
    fits.push_back([&, k] {
      ModelOutcome& m = result.candidates[k];
      std::vector<const Candidate*> effects;
      for (const std::string& name : m.effects) effects.push_back(&candidateByName(name));
      say("candidate " + m.label + " by continuation");
      ModelOutcome again = fitByContinuation(effects, base);
      again_evaluations[k] = again.evaluations;
      if (again.fitted) judge(again, base);
      m = betterOf(std::move(m), std::move(again));
    });
  }
  runFits(fits);
  for (int evaluations : again_evaluations) result.total_evaluations += evaluations;
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
    std::vector<std::optional<ModelOutcome>> tried(result.candidates.size());
    std::vector<std::function<void()>> fits;
    for (size_t k = 0; k < result.candidates.size(); ++k) {
      const ModelOutcome& m = result.candidates[k];
      // every other fitted candidate: a second effect can be masked by the first one's larger
      // discrepancy, so that on its own it does not even lower the held-out error
      if (!m.fitted || m.label == first.label) continue;
      fits.push_back([&, k] {
        const ModelOutcome& second = result.candidates[k];
        std::vector<const Candidate*> pair{&candidateByName(first.effects[0]),
                                           &candidateByName(second.effects[0])};
        // docs/model.md 7.6: with cross validation, no model with more parameters than a fold
        // trains rows (each row is one motor rate)
        const size_t parameters = first.parameters.size() + pair[1]->variables.size();
        if (folds_ && static_cast<int>(parameters) > fewestTrainingRows()) {
          say("  " + first.label + " + " + second.label +
              formatted(" not tried: %.0f parameters, more than the %.0f rows a fold trains on",
                        parameters, fewestTrainingRows()));
          return;
        }
        tried[k] = fitModelOutcome(pair, first);
      });
    }
    runFits(fits);
    for (std::optional<ModelOutcome>& combined : tried) {
      if (!combined) continue;
      result.total_evaluations += combined->evaluations;
      result.combinations.push_back(std::move(*combined));
    }
    if (const ModelOutcome* best_pair = bestSignificant(result.combinations)) {
      chosen = *best_pair;
      if (options_.pair_rule) checkPairAgainstItsSingles(result, chosen);
    }
  }
}

}  // namespace identify
}  // namespace flagella
