#include "flagella_identify/fit.h"

#include <ceres/ceres.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

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
    const int m = num_residuals();
    const std::vector<double> u(parameters[0], parameters[0] + n);
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    // Ceres asks for the same point more than once (cost, then cost and Jacobian): reuse it.
    if (u == cached_u_ && (!want_jacobian || cached_has_jacobian_)) {
      std::copy(cached_r_.begin(), cached_r_.end(), residuals);
      if (want_jacobian) std::copy(cached_j_.begin(), cached_j_.end(), jacobians[0]);
      return cached_ok_;
    }
    std::vector<std::vector<double>> points{coords_.values(u.data())};
    std::vector<double> steps(n, 0.0);
    if (want_jacobian) {
      for (int k = 0; k < n; ++k) {
        const FitParameter& p = coords_.parameters[coords_.free_index[k]];
        steps[k] = p.log_scale ? options_.log_step : options_.linear_step * (p.upper - p.lower);
        // Step inward at the upper bound so the perturbed point stays in range.
        if (u[k] + steps[k] > coords_.upperU(k)) steps[k] = -steps[k];
        std::vector<double> shifted = u;
        shifted[k] += steps[k];
        points.push_back(coords_.values(shifted.data()));
      }
    }
    std::vector<Evaluation> evals = evaluator_.evaluateMany(model_, points, Part::kTrain);
    *evaluations_ += static_cast<int>(points.size());
    // A perturbed model that cannot be simulated: difference the other way instead.
    for (int k = 0; want_jacobian && evals[0].ok && k < n; ++k) {
      if (evals[k + 1].ok) continue;
      steps[k] = -steps[k];
      std::vector<double> shifted = u;
      shifted[k] += steps[k];
      evals[k + 1] = evaluator_.evaluate(model_, coords_.values(shifted.data()), Part::kTrain);
      *evaluations_ += 1;
    }
    cached_u_ = u;
    cached_has_jacobian_ = want_jacobian;
    cached_ok_ = false;
    for (const Evaluation& e : evals)
      if (!e.ok || static_cast<int>(e.points.size()) != m) return false;
    cached_r_.assign(m, 0.0);
    for (int i = 0; i < m; ++i) cached_r_[i] = evals[0].points[i].z();
    std::copy(cached_r_.begin(), cached_r_.end(), residuals);
    if (want_jacobian) {
      cached_j_.assign(static_cast<size_t>(m) * n, 0.0);
      for (int k = 0; k < n; ++k)
        for (int i = 0; i < m; ++i)
          cached_j_[i * n + k] = (evals[k + 1].points[i].z() - cached_r_[i]) / steps[k];
      std::copy(cached_j_.begin(), cached_j_.end(), jacobians[0]);
    }
    cached_ok_ = true;
    return true;
  }

 private:
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

}  // namespace

FitResult fitModel(Model& model, const Evaluator& evaluator, const FitOptions& options,
                   const std::vector<bool>& free) {
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

  if (n > 0) {
    ceres::Problem problem;
    auto* cost = new SimulationResiduals(model, evaluator, coords, options, result.residual_count,
                                         &result.evaluations);
    problem.AddResidualBlock(cost, nullptr, u.data());
    for (int k = 0; k < n; ++k) {
      problem.SetParameterLowerBound(u.data(), k, coords.lowerU(k));
      problem.SetParameterUpperBound(u.data(), k, coords.upperU(k));
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = options.max_iterations;
    so.function_tolerance = options.function_tolerance;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ProgressCallback callback(options);
    so.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    result.iterations = static_cast<int>(summary.iterations.size());
    result.message = summary.message;
    if (!summary.IsSolutionUsable()) {
      result.message = "the fit did not produce a usable solution: " + summary.message;
      return result;
    }
  }
  result.values = coords.values(u.data());
  result.sigma.assign(result.values.size(), 0.0);

  // Covariance of u from the Jacobian at the optimum: (J^T J)^+ (known measurement noise).
  const SimulationResiduals at_optimum(model, evaluator, coords, options, result.residual_count,
                                       &result.evaluations);
  std::vector<double> r(result.residual_count);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(result.residual_count,
                                                                           std::max(n, 1));
  const double* params[] = {u.data()};
  double* jac[] = {J.data()};
  if (n > 0 && at_optimum.Evaluate(params, r.data(), jac)) {
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
  } else {
    const Evaluation end = evaluator.evaluate(model, result.values, Part::kTrain);
    result.chi_square = chiSquare(end);
  }
  model.setValues(result.values);
  for (size_t i = 0; i < result.values.size(); ++i)
    model.parameters()[i].uncertainty = result.sigma[i];
  result.ok = true;
  return result;
}

}  // namespace identify
}  // namespace flagella
