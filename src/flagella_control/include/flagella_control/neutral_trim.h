// The slider's neutral position (no COM-COV couple) from how the head pitches (docs/model.md
// 7.4). The head axis's elevation e obeys de/dt = k cos(e) (x - x_n), with k the calibrated
// pitch rate per slider metre and x the slider command; with S = int k cos(e) x dt and
// C = int k cos(e) dt, e - S = e_0 - x_n C: the least-squares line of e - S over C gives x_n.
// Fixed size, no allocation: a firmware-shaped accumulator.
#pragma once

#include <algorithm>
#include <cmath>

namespace flagella::control {

class NeutralTrim {
 public:
  void reset() { *this = NeutralTrim{}; }
  /// One sample: the time since the last, the head axis's elevation [rad] now, the slider
  /// command held over that interval [m] and the calibrated pitch rate per slider metre.
  void add(double dt, double elevation, double slider, double pitch_rate_per_slider) {
    const double rate = pitch_rate_per_slider * std::cos(elevation);
    if (samples_ > 0) {
      driven_ += rate * slider * dt;
      exposure_ += rate * dt;
    }
    const double y = elevation - driven_, x = exposure_;
    ++samples_;
    sx_ += x, sy_ += y, sxx_ += x * x, sxy_ += x * y, syy_ += y * y;
  }
  long samples() const { return samples_; }
  /// The neutral estimate [m] (NaN before three samples).
  double neutral() const {
    const double d = centred(sxx_, sx_, sx_);
    return samples_ >= 3 && d > 0.0 ? -centred(sxy_, sx_, sy_) / d : NAN;
  }
  /// Standard error of that estimate [m] from the scatter about the line (NaN before three).
  double standardError() const {
    const double d = centred(sxx_, sx_, sx_);
    if (samples_ < 3 || d <= 0.0) return NAN;
    const double b = centred(sxy_, sx_, sy_) / d;
    const double residual = std::max(0.0, centred(syy_, sy_, sy_) - b * b * d);
    return std::sqrt(residual / static_cast<double>(samples_ - 2) / d);
  }

 private:
  // sum (a - mean a)(b - mean b) from raw sums.
  double centred(double sab, double sa, double sb) const {
    return sab - sa * sb / static_cast<double>(samples_);
  }
  long samples_ = 0;
  double driven_ = 0.0, exposure_ = 0.0;
  double sx_ = 0.0, sy_ = 0.0, sxx_ = 0.0, sxy_ = 0.0, syy_ = 0.0;
};

}  // namespace flagella::control
