// Least-squares fit of a model's parameters to the training part of a data set (Ceres
// Levenberg-Marquardt, or Brent's method for one parameter of a cost too rough to difference;
// every residual evaluation runs the simulations), with the covariance of the estimate from the
// Jacobian at the optimum.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "flagella_identify/evaluation.h"

namespace flagella {
namespace identify {

struct FitOptions {
  int max_iterations = 25;
  double function_tolerance = 1e-4;  ///< relative change of the cost that ends the fit
  /// Trials of the projected line search along each trust-region step (0: none). Measured on
  /// the helical robot's tables: near the optimum a rejected step's trials shrink toward the
  /// current point and fail, each trial a model evaluation (with cubic interpolation 1 + n).
  int max_line_search_trials = 0;
  double log_step = 1e-3;     ///< finite-difference step of log-scale parameters
  double linear_step = 1e-5;  ///< ... of linear parameters, as a fraction of their range
  /// One free parameter: minimise chi^2 without derivatives (downhill bracketing, then Brent's
  /// method), for outputs that scatter with the model (buckling thresholds, docs/model.md
  /// 8.4.5). More free parameters still use Levenberg-Marquardt.
  bool derivative_free = false;
  double bracket_step = 0.2;        ///< derivative-free: first step (log scale; else x the range)
  double bracket_tolerance = 0.04;  ///< derivative-free: final bracket width (same units)
  /// Called with a line of progress text.
  std::function<void(const std::string&)> progress;
};

struct FitResult {
  bool ok = false;
  std::string message;
  std::vector<double> values;
  std::vector<double> sigma;  ///< one standard deviation per parameter (NaN: not identifiable)
  double chi_square = 0.0;    ///< training sum of squared normalised residuals
  int residual_count = 0;
  int evaluations = 0;  ///< model evaluations (each one simulates the training set)
  int iterations = 0;
  std::string method;  ///< "Levenberg-Marquardt" or "Brent"
  /// The optimiser met its convergence test (false: it stopped at its iteration limit or
  /// could not go on), and the largest gradient component at the end, in the fit coordinates
  /// (NaN for Brent, which uses no gradient).
  bool converged = false;
  double gradient_max_norm = std::numeric_limits<double>::quiet_NaN();
};

/// What puts a fitted parameter off its map (docs/model.md 7.6), one line each: ended within a
/// thousandth of its range (in the fit coordinate) of a bound, or with a one-sigma uncertainty
/// wider than its whole range, or none at all (not identifiable). Empty: every one is inside.
std::vector<std::string> offTheMap(const std::vector<FitParameter>& parameters);

/// Throws std::invalid_argument naming the first field out of its range.
void validateFitOptions(const FitOptions& options);

/// Fits the parameters whose `free` flag is set (all if empty), starting from model values.
/// The model's values are set to the result. It never ends above its start: should the
/// optimiser, the start values are kept (sigma NaN, said in the message). Bad options are
/// refused before any simulation (validateFitOptions).
FitResult fitModel(Model& model, const Evaluator& evaluator, const FitOptions& options,
                   const std::vector<bool>& free = {});

}  // namespace identify
}  // namespace flagella
