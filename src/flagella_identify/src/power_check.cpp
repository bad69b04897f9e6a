#include "flagella_identify/power_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "flagella_identify/calibration.h"
#include "flagella_identify/chi_square.h"
#include "flagella_identify/model.h"
#include "series_features.h"

namespace flagella {
namespace identify {

namespace {

/// The data's row configurations: each table's common overrides plus each distinct set of row
/// overrides, in order of appearance.
std::vector<std::vector<ConfigOverride>> rowConfigurations(const SteadyStateTable& table) {
  std::vector<std::vector<ConfigOverride>> out;
  for (const SteadyStateRow& row : table.rows)
    if (std::find(out.begin(), out.end(), row.overrides) == out.end()) out.push_back(row.overrides);
  return out;
}

/// The uncertainty of each steady output a table measures: the table's noise, else the median of
/// its rows' own.
std::map<std::string, double> typicalNoise(const SteadyStateTable& table) {
  std::map<std::string, std::vector<double>> seen;
  for (const SteadyStateRow& row : table.rows)
    for (const auto& [output, value] : row.measured) {
      const double sigma = row.sigmaOf(output, table.noise);
      if (output != "buckling_threshold" && std::isfinite(value) && sigma > 0.0)
        seen[output].push_back(sigma);
    }
  std::map<std::string, double> out;
  for (auto& [output, sigmas] : seen) {
    if (const auto it = table.noise.find(output); it != table.noise.end()) {
      out[output] = it->second;
      continue;
    }
    std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
    out[output] = sigmas[sigmas.size() / 2];
  }
  return out;
}

/// The data's signed motor rates [rad/s]: the tables' rows, else the series' commands.
std::vector<double> dataRates(const MeasuredData& data) {
  std::vector<double> rates;
  for (const SteadyStateTable& t : data.tables)
    for (const SteadyStateRow& row : t.rows) rates.push_back(row.omega_T);
  if (rates.empty())
    for (const TimeSeries& s : data.series)
      rates.insert(rates.end(), s.omega_cmd.begin(), s.omega_cmd.end());
  return rates;
}

/// The grid of signed rates [rad/s]: a quarter of the lowest |omega_T| to twice the highest,
/// geometric, with the sign of the fastest.
std::vector<double> suggestionRates(const MeasuredData& data) {
  double low = std::numeric_limits<double>::infinity(), high = 0.0, sign = 1.0;
  for (double omega : dataRates(data)) {
    const double w = std::abs(omega);
    if (!(w > 0.0)) continue;
    low = std::min(low, w);
    if (w > high) {
      high = w;
      sign = omega < 0.0 ? -1.0 : 1.0;
    }
  }
  std::vector<double> rates;
  if (!(high > 0.0)) return rates;
  const double first = 0.25 * low, last = 2.0 * high;
  for (int k = 0; k < kSuggestionRates; ++k)
    rates.push_back(sign * first * std::pow(last / first, k / (kSuggestionRates - 1.0)));
  return rates;
}

/// The longest stretch of constant command in a series [s].
double longestStretch(const TimeSeries& s) {
  double longest = 0.0;
  for (size_t i = 0, j = 0; i < s.t.size(); i = j) {
    while (j < s.t.size() && s.omega_cmd[j] == s.omega_cmd[i]) ++j;
    longest = std::max(longest, s.t[j - 1] - s.t[i]);
  }
  return longest;
}

/// docs/model.md 7.6: the steady run a series' instruments would measure, as a table without
/// rows: as long as the series' longest stretch of constant command, its first quarter to
/// settle; the speed from two tracked positions a window apart (sigma sqrt(2) sigma_p / T), the
/// rates from counted turns (sigma 2 pi sqrt(2) sigma_turns / T).
SteadyStateTable steadyRunOf(const TimeSeries& s) {
  SteadyStateTable t;
  t.source = s.source;
  const double stretch = longestStretch(s);
  t.settle_time = kFeatureSettleShare * stretch;
  t.window = stretch - t.settle_time;
  t.overrides = s.overrides;
  if (!(t.window > 0.0)) return t;
  if (!s.position.empty() && s.position_noise > 0.0)
    t.noise["v"] = std::sqrt(2.0) * s.position_noise / t.window;
  const double rate_sigma = 2.0 * M_PI * std::sqrt(2.0) * s.turns_noise / t.window;
  if (!s.head_turns.empty() && s.turns_noise > 0.0) t.noise["omega_h"] = rate_sigma;
  if (!s.tail_turns.empty() && s.turns_noise > 0.0) t.noise["omega_t"] = rate_sigma;
  return t;
}

/// The tables the grid is built on: the data's tables, else one steady run per series (one row,
/// taken after the series for drift effects, whose configuration is the series').
std::vector<SteadyStateTable> gridTemplates(const MeasuredData& data) {
  std::vector<SteadyStateTable> out = data.tables;
  if (out.empty())
    for (const TimeSeries& s : data.series) {
      SteadyStateTable t = steadyRunOf(s);
      SteadyStateRow at_end;
      at_end.time = s.session_time + (s.t.empty() ? 0.0 : s.t.back());
      for (const auto& entry : t.noise) at_end.measured[entry.first] = 0.0;
      t.rows.push_back(at_end);
      out.push_back(t);
    }
  return out;
}

/// One table per template: the grid rates x its row configurations, each measuring the
/// template's steady outputs that have a noise (value 0: only the model side is used).
MeasuredData suggestionGrid(const MeasuredData& data) {
  MeasuredData grid;
  const std::vector<double> rates = suggestionRates(data);
  for (const SteadyStateTable& t : gridTemplates(data)) {
    SteadyStateTable g = t;
    g.rows.clear();
    double latest = kMissing;  // drift effects: the grid's rows are taken last in the session
    for (const SteadyStateRow& row : t.rows)
      if (std::isfinite(row.time) && !(row.time <= latest)) latest = row.time;
    for (const std::vector<ConfigOverride>& overrides : rowConfigurations(t))
      for (double omega : rates) {
        SteadyStateRow row;
        row.omega_T = omega;
        row.time = latest;
        row.overrides = overrides;
        for (const auto& [output, sigma] : typicalNoise(t)) {
          row.measured[output] = 0.0;
          row.sigma[output] = sigma;
        }
        if (!row.measured.empty()) g.rows.push_back(row);
      }
    if (!g.rows.empty()) grid.tables.push_back(g);
  }
  return grid;
}

}  // namespace

std::string configurationText(const SuggestedMeasurement& s) {
  std::string text;
  for (const ConfigOverride& o : s.overrides)
    text += (text.empty() ? "" : ", ") + o.first + " " + o.second;
  return text;
}

namespace {

double weakerEnd(const TypicalStrength& t, const FitParameter& variable, const double* off) {
  if (off == nullptr) return t.low;
  // The end nearer the value at which the effect vanishes, in the variable's fit coordinate: a
  // ratio whose realistic range lies below its off value of 1 is weakest at the range's high end
  auto distance = [&](double v) {
    return variable.log_scale && v > 0.0 && *off > 0.0 ? std::abs(std::log(v / *off))
                                                       : std::abs(v - *off);
  };
  return distance(t.high) < distance(t.low) ? t.high : t.low;
}

}  // namespace

std::vector<double> weakestTypicalStrength(const Candidate& c, const YAML::Node& baseline) {
  std::vector<double> strength;
  bool any = false;
  for (size_t i = 0; i < c.variables.size(); ++i) {
    const double* off = c.off.size() > i ? &c.off[i] : nullptr;
    double value = off ? *off : c.variables[i].value;
    for (const TypicalStrength& t : typicalStrengths(c, baseline))
      if (t.variable == c.variables[i].name) {
        value = weakerEnd(t, c.variables[i], off);
        any = true;
      }
    strength.push_back(value);
  }
  return any ? strength : std::vector<double>{};
}

PowerCheck checkPower(const Model& baseline, const std::vector<double>& baseline_values,
                      double baseline_chi_square, int count, const Candidate& candidate,
                      const Evaluator& all_rows, const FitOptions& fit) {
  PowerCheck out;
  out.candidate = candidate.name;
  out.strength = weakestTypicalStrength(candidate, baseline.extendedConfig());
  if (out.strength.empty()) {
    out.note = "no realistic strength is known for it";
    return out;
  }
  Model model = baseline;
  model.addCandidate(candidate);
  std::vector<double> values = baseline_values;
  values.insert(values.end(), out.strength.begin(), out.strength.end());
  model.setValues(values);
  std::vector<bool> free(values.size(), false);
  std::fill(free.begin(), free.begin() + model.baselineCount(), true);
  FitOptions options = fit;
  options.progress = nullptr;
  const FitResult r = fitModel(model, all_rows, options, free);
  out.evaluations = r.evaluations;
  if (!r.ok) {
    out.note = "the model with the effect could not be fitted: " + r.message;
    return out;
  }
  out.checked = true;
  out.values = r.values;
  out.chi_square_increase = r.chi_square - baseline_chi_square;
  // docs/model.md 7.6: the selection's bar, critical value + parsimony penalty
  const int k = static_cast<int>(out.strength.size());
  out.threshold = chiSquareCritical(k) + k * std::log(static_cast<double>(std::max(2, count)));
  out.excluded = out.chi_square_increase > out.threshold;
  return out;
}

std::vector<SuggestedMeasurement> suggestMeasurements(const Model& baseline,
                                                      const std::vector<double>& baseline_values,
                                                      const PowerCheck& check,
                                                      const MeasuredData& data,
                                                      const EvaluatorOptions& options) {
  if (!check.checked) return {};
  Model with_effect = baseline;
  with_effect.addCandidate(candidateByName(check.candidate));
  return separatingMeasurements({"baseline", &baseline, baseline_values},
                                {check.candidate, &with_effect, check.values}, data, options);
}

std::vector<SuggestedMeasurement> separatingMeasurements(const LabelledModel& reference,
                                                         const LabelledModel& candidate,
                                                         const MeasuredData& data,
                                                         const EvaluatorOptions& options) {
  std::vector<SuggestedMeasurement> out;
  const MeasuredData grid = suggestionGrid(data);
  if (grid.tables.empty()) return out;
  const Evaluator evaluator(grid, trainingOnlySplit(grid), options);
  const Evaluation ref = evaluator.evaluate(*reference.model, reference.values, Part::kAll);
  const Evaluation cand = evaluator.evaluate(*candidate.model, candidate.values, Part::kAll);
  if (!ref.ok || !cand.ok || ref.points.size() != cand.points.size()) return out;
  std::vector<SuggestedMeasurement> all;
  for (size_t i = 0; i < ref.points.size(); ++i) {
    const ResidualPoint& b = ref.points[i];
    SuggestedMeasurement s;
    s.candidate = candidate.label;
    s.reference = reference.label;
    s.omega_T = b.omega_T;
    s.output = b.output;
    const SteadyStateTable& table = grid.tables[b.source];
    s.overrides = table.overrides;
    const std::vector<ConfigOverride>& row = table.rows[b.row].overrides;
    s.overrides.insert(s.overrides.end(), row.begin(), row.end());
    s.reference_value = b.model;
    s.candidate_value = cand.points[i].model;
    s.sigma = b.sigma;
    s.separation = std::abs(s.candidate_value - s.reference_value) / s.sigma;
    // a rate where either model's flagellum buckles has no steady speed to measure
    const bool steady = !b.buckled && !cand.points[i].buckled;
    if (steady && s.separation >= kDecisiveSeparation) all.push_back(s);
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const auto& a, const auto& b) { return a.separation > b.separation; });
  std::set<double> rates;
  for (const SuggestedMeasurement& s : all)
    if (static_cast<int>(rates.size()) < kSuggestionsPerCandidate && rates.insert(s.omega_T).second)
      out.push_back(s);
  return out;
}

}  // namespace identify
}  // namespace flagella
