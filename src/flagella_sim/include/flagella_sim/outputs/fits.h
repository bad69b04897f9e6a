// Fitting helpers used to turn simulated robot trajectories into summary metrics: straight-line
// fits (e.g. swimming speed from position vs time), circle fits (radius of a curved trajectory),
// angle unwrapping, frame -> quaternion conversion and root-mean-square values.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <vector>

namespace flagella {

/// Result of an ordinary least-squares fit y ~ slope * x + intercept.
struct LinearFit {
  double slope = 0;
  double intercept = 0;
  /// Coefficient of determination 1 - SS_res / SS_tot; 1 when y is constant (perfect fit).
  double r_squared = 0;
};

/// Ordinary least-squares line through (x[i], y[i]).
/// Throws std::invalid_argument if the sizes differ, there are fewer than 2 points, any value is
/// not finite, or x has (numerically) zero spread.
LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

/// Result of a 2D circle fit.
struct CircleFit {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0;
  /// sqrt(mean((|p_i - center| - radius)^2)), the RMS geometric distance to the circle.
  double rms_residual = 0;
  /// False (with all other fields zero) when no circle could be determined.
  bool valid = false;
};

/// Circle through 2D points: algebraic (Kasa) fit as the initial guess, then Gauss-Newton
/// refinement of the sum of squared geometric distances. Never throws and never returns NaN:
/// valid = false for fewer than 3 points, non-finite input, or (near-)collinear points.
CircleFit fitCircle(const std::vector<Eigen::Vector2d>& points);

/// Removes 2*pi jumps: each consecutive difference is replaced by its representative in
/// [-pi, pi]. The first angle is kept as is; an empty input gives an empty output.
std::vector<double> unwrapAngles(const std::vector<double>& angles);

/// Rotation whose columns are the given frame axes (body axes expressed in the world frame).
/// Slightly non-orthonormal input is projected onto the nearest rotation (columns normalised,
/// then SVD polar decomposition). Returns a normalised quaternion with w >= 0.
/// Throws std::invalid_argument for non-finite input or a degenerate (zero-length or
/// linearly dependent) set of axes.
Eigen::Quaterniond quaternionFromFrame(const Eigen::Vector3d& x_axis, const Eigen::Vector3d& y_axis,
                                       const Eigen::Vector3d& z_axis);

/// sqrt(mean(v_i^2)); 0 for an empty vector.
double rootMeanSquare(const std::vector<double>& values);

}  // namespace flagella
