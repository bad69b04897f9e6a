// Validation of small tables (docs/model.md 7.6): below kCrossValidationRows rows (and no time
// series) one held-out split leaves too few rows on either side, and may hold out the only row
// that constrains a parameter. Such data are judged by k-fold cross validation instead: every
// row is predicted by the model fitted without it, except rows that alone constrain a baseline
// parameter, which always train.
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/evaluation.h"

namespace flagella {
namespace identify {

/// Tables with fewer rows than this in all, and no series, are cross-validated: the single
/// split holds out every third row, so below 12 rows it judges on 3 rows or fewer.
constexpr int kCrossValidationRows = 12;
/// At most this many folds (leave-one-out up to this many rows); each fold costs one refit of
/// every model.
constexpr int kMaxFolds = 6;
/// Each fold refits a model from its all-rows optimum by at most this many iterations: the fold's
/// optimum is near, and the refits are most of the cost of cross validation.
constexpr int kFoldIterations = 4;
/// A row constrains a parameter when it carries at least this share of the information about it
/// that the most informative row carries (a tenth: a row ten times weaker adds little).
constexpr double kConstrainingShare = 0.1;

/// True for data judged by cross validation (tables only, fewer than kCrossValidationRows rows).
bool wantsCrossValidation(const MeasuredData& data);

/// information[table][row][parameter]: each row's Fisher information about each parameter.
using RowInformation = std::vector<std::vector<std::vector<double>>>;

/// Each row's Fisher information about each free parameter of `model` at `values`: the sum over
/// the row's residuals of (dz/du)^2 (u the fit coordinate: log for log-scale parameters), by
/// forward differences of `log_step` (log scale) or `linear_step` x the range. `all_rows`
/// evaluates every row (Part::kAll). Only the parameters from `first` on (the others get no
/// column).
RowInformation rowInformation(const Model& model, const std::vector<double>& values,
                              const Evaluator& all_rows, double log_step, double linear_step,
                              size_t first = 0);

struct CrossValidationPlan {
  std::vector<Split> folds;        ///< each fold's held-out rows (series: none)
  std::vector<std::string> notes;  ///< rows that always train and why; parameters no row holds
  int held_out_rows = 0;           ///< rows held out in some fold
  int always_training_rows = 0;
};

/// The folds: rows that alone constrain a parameter always train; the others, in order of
/// |omega_T| per table, are dealt to min(rows, kMaxFolds) folds so that no fold holds out every
/// row that constrains a parameter. `names` label the parameters in the notes.
CrossValidationPlan planFolds(const MeasuredData& data, const RowInformation& information,
                              const std::vector<std::string>& names);

/// How many table rows `split` holds out.
int heldOutRowCount(const Split& split);

/// The held-out rows of any fold, as one split (for plots and reports).
Split heldOutInSomeFold(const MeasuredData& data, const CrossValidationPlan& plan);

}  // namespace identify
}  // namespace flagella
