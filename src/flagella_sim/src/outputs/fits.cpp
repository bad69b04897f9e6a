#include "flagella_sim/outputs/fits.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace flagella {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// fitLine: x is "constant" when its standard deviation is below this fraction of max|x|.
constexpr double kMinRelativeXSpread = 1e-12;

// fitCircle works on points centred on their centroid and scaled to unit RMS distance, so the
// tolerances below are dimensionless.
// Points are (near-)collinear when the minor principal extent of the point cloud is below this
// fraction of the major one (the fitted radius would be ~ 1 / this ratio or larger).
constexpr double kMinCircleSpreadRatio = 1e-6;
// A fitted radius larger than this (in units of the RMS point spread) is rejected as degenerate.
constexpr double kMaxRelativeRadius = 1e8;
constexpr int kMaxGaussNewtonIterations = 100;
// Gauss-Newton stops once the (normalised) parameter step is below this.
constexpr double kGaussNewtonStepTolerance = 1e-13;
// Step halvings tried before a non-decreasing Gauss-Newton step is declared converged.
constexpr int kMaxStepHalvings = 30;
// A point closer than this to the current centre contributes no centre derivative.
constexpr double kMinPointToCenterDistance = 1e-14;

// quaternionFromFrame: axes shorter than this are degenerate; so is a frame whose column-normalised
// determinant (the product of its singular values, each <= sqrt(3)) is below this, i.e. nearly
// linearly dependent axes. A negative determinant is a left-handed frame.
constexpr double kMinAxisLength = 1e-12;
constexpr double kMinNormalisedFrameDeterminant = 1e-8;

bool allFinite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
}

// Sum of squared geometric residuals |q_i - c| - r for normalised points q.
double circleCost(const std::vector<Eigen::Vector2d>& q, const Eigen::Vector3d& params) {
  double cost = 0.0;
  for (const Eigen::Vector2d& p : q) {
    const double d = (p - params.head<2>()).norm() - params(2);
    cost += d * d;
  }
  return cost;
}

}  // namespace

LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) {
    throw std::invalid_argument("fitLine: x and y sizes differ (" + std::to_string(x.size()) +
                                " vs " + std::to_string(y.size()) + ")");
  }
  if (x.size() < 2) throw std::invalid_argument("fitLine: need at least 2 points");
  if (!allFinite(x) || !allFinite(y)) throw std::invalid_argument("fitLine: non-finite input");

  const double n = static_cast<double>(x.size());
  double mean_x = 0.0, mean_y = 0.0, max_abs_x = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i];
    mean_y += y[i];
    max_abs_x = std::max(max_abs_x, std::abs(x[i]));
  }
  mean_x /= n;
  mean_y /= n;

  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double dx = x[i] - mean_x;
    const double dy = y[i] - mean_y;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (std::sqrt(sxx / n) <= kMinRelativeXSpread * max_abs_x || sxx <= 0.0) {
    throw std::invalid_argument("fitLine: x has zero spread");
  }

  LinearFit fit;
  fit.slope = sxy / sxx;
  fit.intercept = mean_y - fit.slope * mean_x;
  // For least squares with an intercept, r^2 = Sxy^2 / (Sxx Syy) = 1 - SS_res / SS_tot.
  fit.r_squared = syy > 0.0 ? std::min(1.0, sxy * sxy / (sxx * syy)) : 1.0;
  return fit;
}

namespace {

// Centroid of the points and their RMS distance from it; false if that is zero or not finite.
bool centroidAndScale(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& centroid,
                      double& scale) {
  const std::size_t n = points.size();
  centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p;
  centroid /= static_cast<double>(n);
  scale = 0.0;
  for (const Eigen::Vector2d& p : points) scale += (p - centroid).squaredNorm();
  scale = std::sqrt(scale / static_cast<double>(n));
  if (!(scale > 0.0) || !std::isfinite(scale)) return false;
  return true;
}

// The points centred and scaled into q; false if they are (near-)collinear.
bool normalisedPoints(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& centroid,
                      double scale, std::vector<Eigen::Vector2d>& q) {
  const std::size_t n = points.size();
  q.reserve(n);
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : points) {
    q.push_back((p - centroid) / scale);
    cov += q.back() * q.back().transpose();
  }
  cov /= static_cast<double>(n);

  // Collinearity: ratio of the principal extents of the point cloud.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov, Eigen::EigenvaluesOnly);
  const double minor = std::max(0.0, eig.eigenvalues()(0));
  const double major = eig.eigenvalues()(1);
  if (!(major > 0.0) || std::sqrt(minor / major) < kMinCircleSpreadRatio) return false;
  return true;
}

// Kasa fit (linear least squares) of centre and radius into params; false if degenerate.
bool kasaCircle(const std::vector<Eigen::Vector2d>& q, Eigen::Vector3d& params) {
  // Minimise sum (x^2 + y^2 + D x + E y + F)^2.
  const std::size_t n = q.size();
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (std::size_t i = 0; i < n; ++i) {
    a.row(i) << q[i].x(), q[i].y(), 1.0;
    b(i) = -q[i].squaredNorm();
  }
  const Eigen::Vector3d def = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d kasa_center = -0.5 * def.head<2>();
  const double kasa_r2 = kasa_center.squaredNorm() - def(2);
  if (!def.allFinite() || !(kasa_r2 > 0.0)) return false;
  params = Eigen::Vector3d(kasa_center.x(), kasa_center.y(), std::sqrt(kasa_r2));
  return true;
}

// Gauss-Newton refinement of params with step halving; returns the final cost.
double gaussNewtonCircle(const std::vector<Eigen::Vector2d>& q, Eigen::Vector3d& params) {
  const std::size_t n = q.size();
  double cost = circleCost(q, params);
  Eigen::MatrixXd jac(n, 3);
  Eigen::VectorXd res(n);
  for (int iter = 0; iter < kMaxGaussNewtonIterations; ++iter) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d diff = q[i] - params.head<2>();
      const double d = diff.norm();
      const Eigen::Vector2d dir =
          d > kMinPointToCenterDistance ? Eigen::Vector2d(diff / d) : Eigen::Vector2d::Zero();
      jac.row(i) << -dir.x(), -dir.y(), -1.0;
      res(i) = d - params(2);
    }
    const Eigen::Vector3d step = jac.colPivHouseholderQr().solve(-res);
    if (!step.allFinite()) break;

    double factor = 1.0;
    bool improved = false;
    for (int h = 0; h <= kMaxStepHalvings; ++h, factor *= 0.5) {
      const Eigen::Vector3d trial = params + factor * step;
      const double trial_cost = circleCost(q, trial);
      if (std::isfinite(trial_cost) && trial_cost <= cost) {
        params = trial;
        cost = trial_cost;
        improved = true;
        break;
      }
    }
    if (!improved || factor * step.norm() < kGaussNewtonStepTolerance) break;
  }
  return cost;
}

}  // namespace

CircleFit fitCircle(const std::vector<Eigen::Vector2d>& points) {
  const CircleFit invalid;
  const std::size_t n = points.size();
  if (n < 3) return invalid;
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) return invalid;
  }

  // Normalise: centroid at the origin, unit RMS distance from it.
  Eigen::Vector2d centroid;
  double scale = 0.0;
  if (!centroidAndScale(points, centroid, scale)) return invalid;
  std::vector<Eigen::Vector2d> q;
  if (!normalisedPoints(points, centroid, scale, q)) return invalid;

  // Kasa estimate, then Gauss-Newton on the geometric residuals |q_i - c| - r, with step halving
  // so that the cost never increases (the result is never worse than the Kasa estimate).
  Eigen::Vector3d params;
  if (!kasaCircle(q, params)) return invalid;
  const double cost = gaussNewtonCircle(q, params);

  if (!params.allFinite() || !(params(2) > 0.0) || params(2) > kMaxRelativeRadius) return invalid;

  CircleFit fit;
  fit.center = centroid + scale * params.head<2>();
  fit.radius = scale * params(2);
  fit.rms_residual = scale * std::sqrt(cost / static_cast<double>(n));
  fit.valid =
      fit.center.allFinite() && std::isfinite(fit.radius) && std::isfinite(fit.rms_residual);
  return fit.valid ? fit : invalid;
}

std::vector<double> unwrapAngles(const std::vector<double>& angles) {
  std::vector<double> out;
  out.reserve(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (i == 0) {
      out.push_back(angles[0]);
    } else {
      // std::remainder maps the jump into [-pi, pi].
      out.push_back(out.back() + std::remainder(angles[i] - angles[i - 1], kTwoPi));
    }
  }
  return out;
}

Eigen::Quaterniond quaternionFromFrame(const Eigen::Vector3d& x_axis, const Eigen::Vector3d& y_axis,
                                       const Eigen::Vector3d& z_axis) {
  Eigen::Matrix3d m;
  m.col(0) = x_axis;
  m.col(1) = y_axis;
  m.col(2) = z_axis;
  if (!m.allFinite()) throw std::invalid_argument("quaternionFromFrame: non-finite axis");
  for (int c = 0; c < 3; ++c) {
    const double len = m.col(c).norm();
    if (len < kMinAxisLength) throw std::invalid_argument("quaternionFromFrame: zero-length axis");
    m.col(c) /= len;
  }
  const double det = m.determinant();
  if (det < 0.0) {
    throw std::invalid_argument("quaternionFromFrame: axes form a left-handed frame");
  }
  if (det < kMinNormalisedFrameDeterminant) {
    throw std::invalid_argument("quaternionFromFrame: axes are (nearly) linearly dependent");
  }

  // Nearest rotation (polar decomposition): R = U diag(1, 1, det(U V^T)) V^T.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  const Eigen::Matrix3d rot = u * v.transpose();

  Eigen::Quaterniond quat(rot);
  quat.normalize();
  if (quat.w() < 0.0) quat.coeffs() = -quat.coeffs();
  return quat;
}

double rootMeanSquare(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

}  // namespace flagella
