#include "flagella_identify/fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>

#include "minimise_one_dimension.h"

namespace flagella {
namespace identify {

namespace {

/// Maps the fitted coordinates u (log of log-scale parameters) to parameter values.
struct Coordinates {
  std::vector<FitParameter> parameters;
  std::vector<int> free_index;  ///< model parameter index of each fitted coordinate
  std::vector<double> fixed;    ///< all values, the free ones overwritten from u

  double toU(int k) const {
    const FitParameter& p = parameters[free_index[k]];
    return p.log_scale ? std::log(p.value) : p.value;
  }
  double lowerU(int k) const {
    const FitParameter& p = parameters[free_index[k]];
    return p.log_scale ? std::log(p.lower) : p.lower;
  }
  double upperU(int k) const {
    const FitParameter& p = parameters[free_index[k]];
    return p.log_scale ? std::log(p.upper) : p.upper;
  }
  std::vector<double> values(const double* u) const {
    std::vector<double> v = fixed;
    for (size_t k = 0; k < free_index.size(); ++k) {
      const FitParameter& p = parameters[free_index[k]];
      v[free_index[k]] = p.log_scale ? std::exp(u[k]) : u[k];
    }
    return v;
  }
};

/// The residual vector of the training set as a Ceres cost function; the Jacobian is a
/// forward difference whose perturbed models are simulated in parallel.
class SimulationResiduals : public ceres::CostFunction {
 public:
  SimulationResiduals(const Model& model, const Evaluator& evaluator, const Coordinates& coords,
                      const FitOptions& options, int residuals, int* evaluations)
      : model_(model),
        evaluator_(evaluator),
        coords_(coords),
        options_(options),
        evaluations_(evaluations) {
    set_num_residuals(residuals);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(coords.free_index.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = static_cast<int>(coords_.free_index.size());
    const std::vector<double> u(parameters[0], parameters[0] + n);
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    // Ceres asks for the same point more than once (cost, then cost and Jacobian): reuse it,
    // and when only the Jacobian is new, simulate only the perturbed models.
    const bool known = u == cached_u_;
    if (known && !cached_ok_) return false;
    if (!known) {
      cached_u_ = u;
      cached_has_jacobian_ = false;
      cached_ok_ = residualsOf(evaluator_.evaluate(model_, coords_.values(u.data()), Part::kTrain),
                               cached_r_);
      *evaluations_ += 1;
      if (!cached_ok_) return false;
    }
    std::copy(cached_r_.begin(), cached_r_.end(), residuals);
    if (!want_jacobian) return true;
    if (!cached_has_jacobian_) {
      if (!jacobianAt(u)) return false;
      cached_has_jacobian_ = true;
    }
    std::copy(cached_j_.begin(), cached_j_.end(), jacobians[0]);
    return true;
  }

  /// Seeds the cache with an evaluation already made at `u`.
  void prime(const std::vector<double>& u, const Evaluation& e) const {
    cached_u_ = u;
    cached_has_jacobian_ = false;
    cached_ok_ = residualsOf(e, cached_r_);
  }

 private:
  /// The normalised residuals of an evaluation; false if it failed or has the wrong size.
  bool residualsOf(const Evaluation& e, std::vector<double>& r) const {
    if (!e.ok || static_cast<int>(e.points.size()) != num_residuals()) return false;
    r.resize(e.points.size());
    for (size_t i = 0; i < r.size(); ++i) r[i] = e.points[i].z();
    return true;
  }

  /// Forward-difference Jacobian at `u` (base residuals in cached_r_) into cached_j_; the
  /// perturbed models are simulated in parallel.
  bool jacobianAt(const std::vector<double>& u) const {
    const int n = static_cast<int>(u.size());
    const int m = num_residuals();
    std::vector<double> steps(n);
    std::vector<std::vector<double>> points;
    for (int k = 0; k < n; ++k) {
      const FitParameter& p = coords_.parameters[coords_.free_index[k]];
      steps[k] = p.log_scale ? options_.log_step : options_.linear_step * (p.upper - p.lower);
      // Step inward at the upper bound so the perturbed point stays in range.
      if (u[k] + steps[k] > coords_.upperU(k)) steps[k] = -steps[k];
      std::vector<double> shifted = u;
      shifted[k] += steps[k];
      points.push_back(coords_.values(shifted.data()));
    }
    const std::vector<Evaluation> evals = evaluator_.evaluateMany(model_, points, Part::kTrain);
    *evaluations_ += n;
    cached_j_.assign(static_cast<size_t>(m) * n, 0.0);
    std::vector<double> shifted_r;
    for (int k = 0; k < n; ++k) {
      if (!residualsOf(evals[k], shifted_r)) {
        // A perturbed model that cannot be simulated: difference the other way instead.
        steps[k] = -steps[k];
        std::vector<double> shifted = u;
        shifted[k] += steps[k];
        *evaluations_ += 1;
        if (!residualsOf(evaluator_.evaluate(model_, coords_.values(shifted.data()), Part::kTrain),
                         shifted_r))
          return false;
      }
      for (int i = 0; i < m; ++i) cached_j_[i * n + k] = (shifted_r[i] - cached_r_[i]) / steps[k];
    }
    return true;
  }

  const Model& model_;
  const Evaluator& evaluator_;
  const Coordinates& coords_;
  const FitOptions& options_;
  int* evaluations_;
  mutable std::vector<double> cached_u_, cached_r_, cached_j_;
  mutable bool cached_has_jacobian_ = false, cached_ok_ = false;
};

class ProgressCallback : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(const FitOptions& options) : options_(options) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (options_.progress) {
      char line[160];
      std::snprintf(line, sizeof line, "    iteration %2d: chi^2 = %.4g", s.iteration,
                    2.0 * s.cost);
      options_.progress(line);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const FitOptions& options_;
};

/// Minimises the cost over `u` (in place) within the coordinates' bounds; false (with the
/// message in `result`) if Ceres gives no usable solution.
bool solve(SimulationResiduals& cost, const Coordinates& coords, const FitOptions& options,
           std::vector<double>& u, FitResult& result) {
  const int n = static_cast<int>(u.size());
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  problem.AddResidualBlock(&cost, nullptr, u.data());
  for (int k = 0; k < n; ++k) {
    problem.SetParameterLowerBound(u.data(), k, coords.lowerU(k));
    problem.SetParameterUpperBound(u.data(), k, coords.upperU(k));
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  // With bounds, Ceres refines every trust-region step by a projected Armijo line search (off
  // when max_line_search_trials is 0: the step is then projected onto the bounds and judged by
  // the trust region alone). Its trials ask for the cost only (bisection): the default cubic
  // interpolation wants the gradient at each, here n more simulations.
  so.line_search_interpolation_type = ceres::BISECTION;
  so.max_num_line_search_step_size_iterations = options.max_line_search_trials;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ProgressCallback callback(options);
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.message = summary.message;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  if (!summary.iterations.empty())
    result.gradient_max_norm = summary.iterations.back().gradient_max_norm;
  if (!summary.IsSolutionUsable()) {
    result.message = "the fit did not produce a usable solution: " + summary.message;
    return false;
  }
  return true;
}

/// Minimises chi^2 over the one free coordinate u[0] without derivatives (bracketing + Brent);
/// the cost's cache is left holding the best evaluation. False (message in `result`) if no
/// point could be evaluated.
bool solveAlongOne(SimulationResiduals& cost, const Model& model, const Evaluator& evaluator,
                   const Coordinates& coords, const FitOptions& options, const Evaluation& start,
                   std::vector<double>& u, FitResult& result) {
  const FitParameter& p = coords.parameters[coords.free_index[0]];
  const double scale = p.log_scale ? 1.0 : p.upper - p.lower;
  OneDimensionOptions o;
  o.lower = coords.lowerU(0);
  o.upper = coords.upperU(0);
  o.step = options.bracket_step * scale;
  o.tolerance = options.bracket_tolerance * scale;
  o.max_evaluations = std::max(4, 2 * options.max_iterations);
  double best_chi = chiSquare(start);
  Evaluation best = start;
  std::map<double, double> seen = {{u[0], best_chi}};  // Brent may ask for a point again
  auto costs = [&](const std::vector<double>& xs) {
    std::vector<double> fresh;
    std::vector<std::vector<double>> points;
    // A point already seen, within a thousandth of the final bracket (golden sections of the
    // bracket fall on the bracketing points up to rounding).
    const double same = 1e-3 * o.tolerance;
    auto known = [&](double x) {
      const auto it = seen.lower_bound(x - same);
      return it != seen.end() && std::abs(it->first - x) <= same ? it : seen.end();
    };
    for (double x : xs)
      if (known(x) == seen.end() && std::find(fresh.begin(), fresh.end(), x) == fresh.end()) {
        fresh.push_back(x);
        points.push_back(coords.values(&x));
      }
    const std::vector<Evaluation> evals = evaluator.evaluateMany(model, points, Part::kTrain);
    for (size_t i = 0; i < fresh.size(); ++i) {
      const bool usable =
          evals[i].ok && static_cast<int>(evals[i].points.size()) == result.residual_count;
      const double chi = usable ? chiSquare(evals[i]) : std::numeric_limits<double>::infinity();
      seen[fresh[i]] = chi;
      if (options.progress) {
        char line[200];
        std::snprintf(line, sizeof line, "    %s = %.5g: chi^2 = %.4g%s", p.name.c_str(),
                      points[i][coords.free_index[0]], chi, usable ? "" : " (failed)");
        options.progress(line);
      }
      if (chi < best_chi) {
        best_chi = chi;
        best = evals[i];
      }
    }
    result.evaluations += static_cast<int>(fresh.size());
    std::vector<double> chi;
    for (double x : xs) chi.push_back(known(x)->second);
    return chi;
  };
  const OneDimensionResult r = minimiseOneDimension(costs, u[0], chiSquare(start), o);
  result.iterations = r.evaluations;
  result.message = r.message;
  result.converged = r.ok;  // bracketed and narrowed to its tolerance
  if (!r.ok) return false;
  u[0] = r.x;  // the best point seen, whose evaluation is `best`
  cost.prime(u, best);
  return true;
}

/// Covariance of u from the Jacobian at the optimum, (J^T J)^+ (known measurement noise), into
/// result.sigma, and the training chi^2 from the same evaluation; false if it cannot be
/// evaluated (result.sigma and result.chi_square left unchanged).
bool uncertaintiesAt(const SimulationResiduals& cost, const Coordinates& coords,
                     const std::vector<double>& u, FitResult& result) {
  const int n = static_cast<int>(u.size());
  std::vector<double> r(result.residual_count);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(result.residual_count,
                                                                           std::max(n, 1));
  const double* params[] = {u.data()};
  double* jac[] = {J.data()};
  if (!(n > 0 && cost.Evaluate(params, r.data(), jac))) return false;
  const Eigen::MatrixXd JtJ = J.leftCols(n).transpose() * J.leftCols(n);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(JtJ, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd s = svd.singularValues();
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(n);
  bool deficient = false;
  for (int k = 0; k < n; ++k) {
    if (s(k) > 1e-12 * s(0))
      inv(k) = 1.0 / s(k);
    else
      deficient = true;
  }
  const Eigen::MatrixXd cov = svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose();
  for (int k = 0; k < n; ++k) {
    const int i = coords.free_index[k];
    const double sigma_u = std::sqrt(std::max(cov(k, k), 0.0));
    const FitParameter& p = coords.parameters[i];
    result.sigma[i] = deficient ? std::numeric_limits<double>::quiet_NaN()
                                : (p.log_scale ? result.values[i] * sigma_u : sigma_u);
  }
  result.chi_square = 0.0;
  for (double x : r) result.chi_square += x * x;
  return true;
}

}  // namespace

FitResult fitModel(Model& model, const Evaluator& evaluator, const FitOptions& options,
                   const std::vector<bool>& free) {
  validateFitOptions(options);
  // Ceres reports failed evaluations (a model that cannot be simulated at a trial point) by
  // dumping its state through glog; the fit handles them, so keep stderr for real errors.
  static const bool quiet_glog = [] {
    FLAGS_minloglevel = google::GLOG_FATAL;
    return true;
  }();
  (void)quiet_glog;
  Coordinates coords;
  coords.parameters = model.parameters();
  coords.fixed = model.values();
  for (size_t i = 0; i < coords.parameters.size(); ++i)
    if (free.empty() || free.at(i)) coords.free_index.push_back(static_cast<int>(i));
  const int n = static_cast<int>(coords.free_index.size());

  FitResult result;
  const Evaluation start = evaluator.evaluate(model, coords.fixed, Part::kTrain);
  result.evaluations = 1;
  if (!start.ok) {
    result.message = "the model cannot be simulated at its start values: " + start.failure;
    return result;
  }
  result.residual_count = static_cast<int>(start.points.size());
  std::vector<double> u(n);
  for (int k = 0; k < n; ++k) u[k] = coords.toU(k);

  // One cost function for the fit and the covariance: its cache holds the start evaluation and,
  // usually, the Jacobian at the optimum.
  SimulationResiduals cost(model, evaluator, coords, options, result.residual_count,
                           &result.evaluations);
  cost.prime(u, start);
  const bool along_one = n == 1 && options.derivative_free;
  result.method = along_one ? "Brent" : "Levenberg-Marquardt";
  if (along_one && !solveAlongOne(cost, model, evaluator, coords, options, start, u, result))
    return result;
  if (!along_one && n > 0 && !solve(cost, coords, options, u, result)) return result;
  result.values = coords.values(u.data());
  result.sigma.assign(result.values.size(), 0.0);
  if (!uncertaintiesAt(cost, coords, u, result)) {
    const Evaluation end = evaluator.evaluate(model, result.values, Part::kTrain);
    result.chi_square = chiSquare(end);
  }
  // A fit never ends above its start (a nested model started at the simpler model's optimum
  // can then only improve on it): should the optimiser have, the start is kept.
  if (const double start_chi_square = chiSquare(start); result.chi_square > start_chi_square) {
    result.values = coords.fixed;
    result.sigma.assign(result.values.size(), std::numeric_limits<double>::quiet_NaN());
    result.chi_square = start_chi_square;
    result.message += (result.message.empty() ? "" : "; ") +
                      std::string("the optimiser ended above its start, which is kept");
  }
  model.setValues(result.values);
  for (size_t i = 0; i < result.values.size(); ++i)
    model.parameters()[i].uncertainty = result.sigma[i];
  result.ok = true;
  return result;
}

}  // namespace identify
}  // namespace flagella
