// Derivative-free minimisation of a function of one variable on an interval: downhill bracketing
// from a start point, then Brent's method (Boost.Math). For costs that are not smooth enough to
// difference (a model's buckling threshold scatters by 1-2 % with its search path,
// docs/model.md 8.4.4), where a Gauss-Newton step follows the scatter.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace flagella {
namespace identify {

struct OneDimensionOptions {
  double lower = 0.0, upper = 1.0;  ///< the interval searched
  double step = 0.1;                ///< first bracketing step from the start point, > 0
  double tolerance = 0.01;          ///< about the width of the final bracket, > 0
  int max_evaluations = 40;
};

struct OneDimensionResult {
  bool ok = false;
  double x = 0.0;     ///< the best point evaluated
  double cost = 0.0;  ///< its cost
  int evaluations = 0;
  std::string message;
};

/// Minimises the cost from `x0` (cost `cost0` already known) within [lower, upper]. `costs`
/// evaluates several points at once (they may run in parallel) and returns +infinity for a point
/// that cannot be evaluated. Bracketing evaluates x0 -/+ step together, then walks downhill with
/// steps growing by the golden ratio until the cost rises or the interval ends; Brent's method
/// then narrows the bracket. The result is the best point seen (never worse than x0).
OneDimensionResult minimiseOneDimension(
    const std::function<std::vector<double>(const std::vector<double>&)>& costs, double x0,
    double cost0, const OneDimensionOptions& options);

}  // namespace identify
}  // namespace flagella
