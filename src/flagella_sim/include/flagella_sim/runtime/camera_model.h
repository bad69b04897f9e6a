// A simulated camera fix of the head centre: an overhead camera gives the horizontal position
// (x, y of the output frame, z up); with `stereo` a second camera looking through the tank's side
// adds the height z (its own noise). Low rate, white Gaussian noise, optional dropout window.
#pragma once

#include <Eigen/Core>
#include <random>

#include "flagella_sim/core/types.h"

namespace flagella {

struct CameraOptions {
  double rate = 2.0;       ///< fixes per second of simulated time [Hz]; 0 = off
  double noise_std = 0.0;  ///< per horizontal axis [m]
  bool stereo = false;     ///< two cameras (overhead and side): the fix has a height z
  double height_noise_std = 0.0;  ///< of z with `stereo` [m]
  /// Simulated-time window [dropout_start, dropout_end) without fixes [s]; negative start = none.
  double dropout_start = -1.0, dropout_end = -1.0;
  unsigned seed = 2;

  /// Throws ConfigError naming the field and its range if a value is unusable.
  void validate() const;
  bool enabled() const { return rate > 0.0; }
  /// True inside the dropout window (a 1e-9 s slack absorbs round-off of summed steps).
  bool inDropout(double time) const;
};

struct CameraFix {
  double time = 0.0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< head centre x, y [m], output frame
  double variance = 0.0;                               ///< per axis [m^2]; 0 = noise-free
  bool has_height = false;                             ///< stereo: `height` is measured
  double height = 0.0;           ///< head centre z [m], output frame (0 without stereo)
  double height_variance = 0.0;  ///< [m^2]
};

class CameraModel {
 public:
  /// Throws ConfigError for invalid options.
  explicit CameraModel(CameraOptions options);
  /// Measures the true head centre (output frame, z up): its x, y (and z with stereo) plus
  /// noise.
  CameraFix measure(double time, const Vec3& head_position);
  /// False when the camera is off or inside the dropout window.
  bool available(double time) const { return options_.enabled() && !options_.inDropout(time); }
  const CameraOptions& options() const { return options_; }

 private:
  CameraOptions options_;
  std::mt19937 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
};

}  // namespace flagella
