// Runs a model on the experiments of a data set and returns normalised residuals
// (model - data)/sigma for the training part or the held-out part, with where each residual
// comes from (the diagnosis reads those).
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/data_io.h"
#include "flagella_identify/model.h"
#include "flagella_identify/residuals.h"

namespace flagella {
namespace identify {

enum class Part { kTrain, kHeldOut, kAll };

/// Which experiments train the model and which judge it.
struct Split {
  std::vector<std::vector<bool>> table_row_held_out;  ///< [table][row]
  std::vector<double> series_split_time;  ///< run time from which a series is held out [s]
};

/// A model's buckling threshold is where the growth rate of its flagellum's slow tilt changes
/// sign, searched from the measured value x/ this ratio to this relative tolerance
/// (docs/model.md 8.4.4, 8.4.5).
constexpr double kThresholdBracketRatio = 1.3;
constexpr double kThresholdTolerance = 0.005;

/// Held-out every `stride`-th row of each table in order of |omega_T| (so the held-out rows
/// span the speed range), and the last `held_out_fraction` of each time series.
Split makeSplit(const MeasuredData& data, int stride = 3, double held_out_fraction = 0.4);

struct EvaluatorOptions {
  int jobs = 1;                    ///< simulations run in parallel
  int max_series_points = 240;     ///< residual samples per series (evenly spaced)
  double solver_tolerance = 1e-7;  ///< Newton residual tolerance during identification
  /// Series give phase-free summary features (speed, yaw rate, turn rates per stretch of
  /// constant command; series_features.h) instead of their samples: the first stage of a
  /// continuation fit (docs/model.md 7.6).
  bool series_features = false;
};

class Evaluator {
 public:
  Evaluator(const MeasuredData& data, const Split& split, EvaluatorOptions options = {});

  Evaluation evaluate(const Model& model, const std::vector<double>& values, Part part) const;
  /// Many value vectors at once (the finite-difference Jacobian), simulations in parallel.
  std::vector<Evaluation> evaluateMany(const Model& model,
                                       const std::vector<std::vector<double>>& values,
                                       Part part) const;
  const MeasuredData& data() const { return data_; }
  const Split& split() const { return split_; }
  const EvaluatorOptions& options() const { return options_; }

  using SeriesTrace = identify::SeriesTrace;
  SeriesTrace traceSeries(const Model& model, const std::vector<double>& values, int series,
                          double t_end = 1e300) const;

 private:
  struct Job {
    int model_index;
    bool is_series;
    int source, row;
    int threads = 1;  ///< for the job's own runs (a threshold's window) when jobs > tasks
  };
  void runJob(const Model& model, const std::vector<double>& values, const Job& job, Part part,
              Evaluation& out) const;
  /// One table row: a steady run at the row's motor speed, residuals of its measured outputs.
  void runTableJob(const Model& model, const std::vector<double>& values, const Job& job,
                   Evaluation& out) const;
  /// One series: the simulated run, residuals at the samples of the requested part.
  void runSeriesJob(const Model& model, const std::vector<double>& values, const Job& job,
                    Part part, Evaluation& out) const;

  MeasuredData data_;
  Split split_;
  EvaluatorOptions options_;
};

/// Sum of z^2 and count.
double chiSquare(const Evaluation& e);

}  // namespace identify
}  // namespace flagella
