#include "flagella_identify/cross_validation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "flagella_identify/calibration.h"
#include "flagella_sim/core/units.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

struct RowRef {
  int table = 0, row = 0;
};

std::string rowLabel(const MeasuredData& data, const RowRef& r) {
  const SteadyStateTable& t = data.tables[r.table];
  const SteadyStateRow& row = t.rows[r.row];
  const std::string name = row.id.empty() ? "line " + std::to_string(row.line) : row.id;
  return formatted("row %.0f (", r.row + 1.0) + name +
         formatted(", %.4g rpm) of ", row.omega_T * units::kRpmPerRadPerSec) +
         (t.csv.empty() ? t.source : t.csv);
}

/// The rows constraining each parameter (information >= kConstrainingShare x the largest row's).
std::vector<std::vector<RowRef>> constrainingRows(const RowInformation& info, size_t parameters) {
  std::vector<std::vector<RowRef>> out(parameters);
  for (size_t p = 0; p < parameters; ++p) {
    double largest = 0.0;
    for (const auto& table : info)
      for (const auto& row : table) largest = std::max(largest, row[p]);
    if (!(largest > 0.0)) continue;
    for (size_t t = 0; t < info.size(); ++t)
      for (size_t r = 0; r < info[t].size(); ++r)
        if (info[t][r][p] >= kConstrainingShare * largest)
          out[p].push_back({static_cast<int>(t), static_cast<int>(r)});
  }
  return out;
}

bool same(const RowRef& a, const RowRef& b) { return a.table == b.table && a.row == b.row; }

}  // namespace

bool wantsCrossValidation(const MeasuredData& data) {
  size_t rows = 0;
  for (const SteadyStateTable& t : data.tables) rows += t.rows.size();
  return data.series.empty() && rows > 0 && rows < static_cast<size_t>(kCrossValidationRows);
}

RowInformation rowInformation(const Model& model, const std::vector<double>& values,
                              const Evaluator& all_rows, double log_step, double linear_step,
                              size_t first) {
  const std::vector<FitParameter>& params = model.parameters();
  std::vector<std::vector<double>> points = {values};
  std::vector<double> steps;
  for (size_t k = first; k < params.size(); ++k) {
    const FitParameter& p = params[k];
    std::vector<double> shifted = values;
    // docs/model.md 7.6: dz/du with u = ln(value) for log-scale parameters
    const double step = p.log_scale ? log_step : linear_step * (p.upper - p.lower);
    shifted[k] = p.log_scale ? values[k] * std::exp(step) : values[k] + step;
    steps.push_back(step);
    points.push_back(shifted);
  }
  const std::vector<Evaluation> evals = all_rows.evaluateMany(model, points, Part::kAll);
  RowInformation info;
  for (const SteadyStateTable& t : all_rows.data().tables)
    info.emplace_back(t.rows.size(), std::vector<double>(steps.size(), 0.0));
  const Evaluation& base = evals.front();
  if (!base.ok) throw std::runtime_error("the model cannot be simulated: " + base.failure);
  for (size_t k = 0; k < steps.size(); ++k) {
    const Evaluation& e = evals[k + 1];
    if (!e.ok || e.points.size() != base.points.size()) continue;  // no information from it
    for (size_t i = 0; i < base.points.size(); ++i) {
      const ResidualPoint& p = base.points[i];
      if (p.from_series) continue;
      const double dz = (e.points[i].z() - p.z()) / steps[k];
      info[p.source][p.row][k] += dz * dz;
    }
  }
  return info;
}

CrossValidationPlan planFolds(const MeasuredData& data, const RowInformation& information,
                              const std::vector<std::string>& names) {
  CrossValidationPlan plan;
  const std::vector<std::vector<RowRef>> constraining = constrainingRows(information, names.size());
  std::vector<std::vector<bool>> always(data.tables.size());
  for (size_t t = 0; t < data.tables.size(); ++t)
    always[t].assign(data.tables[t].rows.size(), false);
  for (size_t p = 0; p < names.size(); ++p) {
    if (constraining[p].empty()) plan.notes.push_back(names[p] + " is not constrained by any row");
    if (constraining[p].size() != 1) continue;
    const RowRef& r = constraining[p].front();
    if (!always[r.table][r.row])
      plan.notes.push_back(rowLabel(data, r) +
                           " always trains: it is the only row that "
                           "constrains " +
                           names[p]);
    always[r.table][r.row] = true;
  }
  // The other rows in order of |omega_T| per table, dealt round-robin to the folds.
  std::vector<RowRef> order;
  for (size_t t = 0; t < data.tables.size(); ++t) {
    std::vector<int> rows(data.tables[t].rows.size());
    std::iota(rows.begin(), rows.end(), 0);
    std::stable_sort(rows.begin(), rows.end(), [&](int a, int b) {
      return std::abs(data.tables[t].rows[a].omega_T) < std::abs(data.tables[t].rows[b].omega_T);
    });
    for (int r : rows)
      if (!always[t][r])
        order.push_back({static_cast<int>(t), r});
      else
        ++plan.always_training_rows;
  }
  plan.held_out_rows = static_cast<int>(order.size());
  const int k = std::min(plan.held_out_rows, kMaxFolds);
  std::vector<int> fold_of(order.size());
  for (size_t i = 0; i < order.size(); ++i) fold_of[i] = static_cast<int>(i) % std::max(1, k);
  // No fold may hold out every row that constrains a parameter: move one of them to the next
  // fold, swapping with a row of that fold that does not constrain it.
  auto position = [&](const RowRef& r) {
    for (size_t i = 0; i < order.size(); ++i)
      if (same(order[i], r)) return static_cast<int>(i);
    return -1;
  };
  for (size_t p = 0; p < names.size() && k > 1; ++p) {
    std::vector<int> at;
    for (const RowRef& r : constraining[p])
      if (const int i = position(r); i >= 0) at.push_back(i);
    if (at.size() != constraining[p].size() || at.size() < 2) continue;  // one always trains
    const bool one_fold =
        std::all_of(at.begin(), at.end(), [&](int i) { return fold_of[i] == fold_of[at.front()]; });
    if (!one_fold) continue;
    const int target = (fold_of[at.front()] + 1) % k;
    for (size_t i = 0; i < order.size(); ++i)
      if (fold_of[i] == target &&
          std::find(at.begin(), at.end(), static_cast<int>(i)) == at.end()) {
        fold_of[i] = fold_of[at.front()];
        break;
      }
    fold_of[at.front()] = target;
  }
  for (int f = 0; f < k; ++f) {
    Split split = trainingOnlySplit(data);
    for (size_t i = 0; i < order.size(); ++i)
      if (fold_of[i] == f) split.table_row_held_out[order[i].table][order[i].row] = true;
    plan.folds.push_back(split);
  }
  return plan;
}

int heldOutRowCount(const Split& split) {
  int held = 0;
  for (const auto& table : split.table_row_held_out)
    held += static_cast<int>(std::count(table.begin(), table.end(), true));
  return held;
}

Split heldOutInSomeFold(const MeasuredData& data, const CrossValidationPlan& plan) {
  Split out = trainingOnlySplit(data);
  for (const Split& fold : plan.folds)
    for (size_t t = 0; t < fold.table_row_held_out.size(); ++t)
      for (size_t r = 0; r < fold.table_row_held_out[t].size(); ++r)
        if (fold.table_row_held_out[t][r]) out.table_row_held_out[t][r] = true;
  return out;
}

}  // namespace identify
}  // namespace flagella
