// Where each fit starts (docs/model.md 7.6): the reference's optimum, each new effect's starts.
#include <algorithm>
#include <limits>

#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

/// Where a fit inheriting `reference`'s values starts from, in words.
std::string referenceStartText(const ModelOutcome& reference) {
  return reference.label.empty() ? "the config's values" : "the " + reference.label + " optimum";
}

}  // namespace

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

}  // namespace identify
}  // namespace flagella
