// The slider's neutral position and the pitch rate per slider metre, both learnt from how the
// head pitches over the whole mission (docs/model.md 7.4). The head axis's elevation e obeys
// de/dt = a cos(e) (x - x_n), x the slider command: with s = k int cos(e) (x - x_r) dt (k the
// calibrated pitch rate, x_r a reference position) and c = int cos(e) dt,
// e = e_0 + alpha s + beta c, where alpha = a / k and beta = -a (x_n - x_r). A least-squares fit
// of (e_0, alpha, beta) with exponential forgetting, alpha held toward 1 by a prior, gives
// x_n = x_r - beta / (alpha k). Unlike NeutralTrim (alpha fixed at 1), a pitch rate the model
// gets wrong does not bias the neutral, once the slider has moved (pitching offsets) to show it.
// Fixed size, no allocation: a firmware-shaped accumulator.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace flagella::control {

class PitchModelEstimator {
 public:
  /// calibrated pitch rate per slider metre k [rad/s/m], reference slider position x_r [m],
  /// forgetting time [s], elevation noise per sample [rad] over its correlation time [s], and
  /// the prior's standard deviation of alpha (the relative error of k).
  PitchModelEstimator(double pitch_rate_per_slider = 1.0, double reference = 0.0,
                      double forgetting_time = 120.0, double noise = 0.05,
                      double correlation_time = 5.0, double alpha_sigma = 0.3)
      : k_(pitch_rate_per_slider),
        reference_(reference),
        forgetting_time_(forgetting_time),
        noise_(noise),
        sample_weight_(1.0 / (noise * noise * correlation_time)),
        alpha_precision_(1.0 / (alpha_sigma * alpha_sigma)) {}

  void reset() {
    information_.setZero();
    moment_.setZero();
    square_ = 0.0;
    s_ = c_ = 0.0;
    seconds_ = 0.0;
    started_ = false;
  }

  /// One sample: the time since the last [s], the head axis's elevation now [rad] and the
  /// slider command held over that interval [m].
  void add(double dt, double elevation, double slider) {
    if (started_ && dt > 0.0) {
      const double forget = std::exp(-dt / forgetting_time_);
      information_ *= forget;
      moment_ *= forget;
      square_ *= forget;
      s_ += k_ * std::cos(elevation) * (slider - reference_) * dt;
      c_ += std::cos(elevation) * dt;
      seconds_ += dt;
    }
    started_ = true;
    const Eigen::Vector3d row(1.0, s_, c_);
    const double w = sample_weight_ * std::max(dt, 0.0);
    information_ += w * row * row.transpose();
    moment_ += w * row * elevation;
    square_ += w * elevation * elevation;
  }

  /// Seconds of data since the last reset.
  double seconds() const { return seconds_; }
  /// alpha (the pitch rate over the calibrated one) and the neutral [m], and the neutral's
  /// standard error [m] from the scatter about the fit (samples correlated over the correlation
  /// time); false when the fit is singular.
  bool estimate(double& alpha, double& neutral) const {
    double ignored = NAN;
    return estimate(alpha, neutral, ignored);
  }
  bool estimate(double& alpha, double& neutral, double& standard_error) const {
    Eigen::Matrix3d a = information_;
    Eigen::Vector3d b = moment_;
    a(1, 1) += alpha_precision_;  // prior: alpha = 1
    b(1) += alpha_precision_;
    const Eigen::LDLT<Eigen::Matrix3d> solver(a);
    if (information_(0, 0) <= 0.0 || solver.info() != Eigen::Success || !solver.isPositive() ||
        solver.rcond() < 1e-14)
      return false;
    const Eigen::Vector3d x = solver.solve(b);
    if (!x.allFinite() || x(1) <= 0.0) return false;
    alpha = x(1);
    neutral = reference_ - x(2) / (alpha * k_);
    // Weighted mean square of the residuals over the assumed noise scales the covariance
    // (weights are 1 / (noise^2 correlation time) per second).
    const double residual = std::max(0.0, square_ - 2.0 * x.dot(moment_) + x.dot(information_ * x));
    const double scale = residual / information_(0, 0) / (noise_ * noise_);
    const Eigen::Vector3d gradient(0.0, x(2) / (alpha * alpha * k_), -1.0 / (alpha * k_));
    standard_error = std::sqrt(scale * gradient.dot(solver.solve(gradient)));
    return std::isfinite(neutral);
  }

 private:
  double k_, reference_, forgetting_time_, noise_, sample_weight_, alpha_precision_;
  Eigen::Matrix3d information_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d moment_ = Eigen::Vector3d::Zero();
  double square_ = 0.0;  ///< weighted sum of the squared elevations
  double s_ = 0.0, c_ = 0.0, seconds_ = 0.0;
  bool started_ = false;
};

}  // namespace flagella::control
