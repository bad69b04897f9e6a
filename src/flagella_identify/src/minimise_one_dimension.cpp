#include "minimise_one_dimension.h"

#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace flagella {
namespace identify {

namespace {

constexpr double kGolden = 1.618033988749895;

/// Evaluates points, counts them and remembers the best one seen.
class Recorder {
 public:
  Recorder(const std::function<std::vector<double>(const std::vector<double>&)>& costs,
           OneDimensionResult& result)
      : costs_(costs), result_(result) {}

  std::vector<double> evaluate(const std::vector<double>& xs) {
    std::vector<double> c = costs_(xs);
    if (c.size() != xs.size()) throw std::logic_error("minimiseOneDimension: cost count");
    result_.evaluations += static_cast<int>(xs.size());
    for (size_t i = 0; i < xs.size(); ++i) {
      if (!std::isfinite(c[i])) c[i] = std::numeric_limits<double>::infinity();
      if (c[i] < result_.cost) {
        result_.cost = c[i];
        result_.x = xs[i];
      }
    }
    return c;
  }
  double evaluate(double x) { return evaluate(std::vector<double>{x})[0]; }

 private:
  const std::function<std::vector<double>(const std::vector<double>&)>& costs_;
  OneDimensionResult& result_;
};

/// An interval [a, b] holding a minimum: downhill from x0 by steps growing by the golden ratio.
/// False if the evaluation budget ran out first.
bool bracket(Recorder& recorder, double x0, double cost0, const OneDimensionOptions& o,
             const OneDimensionResult& so_far, double& a, double& b) {
  const double left = std::max(o.lower, x0 - o.step), right = std::min(o.upper, x0 + o.step);
  std::vector<double> sides;
  if (left < x0) sides.push_back(left);
  if (right > x0) sides.push_back(right);
  const std::vector<double> c = recorder.evaluate(sides);
  const double inf = std::numeric_limits<double>::infinity();
  const double cost_left = left < x0 ? c.front() : inf;
  const double cost_right = right > x0 ? c.back() : inf;
  if (cost_left >= cost0 && cost_right >= cost0) {  // x0 is lowest: done
    a = left;
    b = right;
    return true;
  }
  const double direction = cost_right < cost_left ? 1.0 : -1.0;
  double previous = x0, current = direction > 0 ? right : left;
  double current_cost = std::min(cost_left, cost_right);
  double step = std::abs(current - previous);
  while (true) {
    const double bound = direction > 0 ? o.upper : o.lower;
    if (current == bound) break;  // the minimum lies between previous and the bound
    if (so_far.evaluations >= o.max_evaluations) return false;
    step *= kGolden;
    const double next = direction > 0 ? std::min(bound, current + step)  //
                                      : std::max(bound, current - step);
    const double next_cost = recorder.evaluate(next);
    if (next_cost >= current_cost) {
      current = next;
      break;
    }
    previous = current;
    current = next;
    current_cost = next_cost;
  }
  a = std::min(previous, current);
  b = std::max(previous, current);
  return true;
}

}  // namespace

OneDimensionResult minimiseOneDimension(
    const std::function<std::vector<double>(const std::vector<double>&)>& costs, double x0,
    double cost0, const OneDimensionOptions& o) {
  if (!(o.lower <= x0 && x0 <= o.upper && o.step > 0.0 && o.tolerance > 0.0))
    throw std::invalid_argument(
        "minimiseOneDimension: need lower <= x0 <= upper, step > 0, "
        "tolerance > 0");
  OneDimensionResult result;
  result.x = x0;
  result.cost = std::isfinite(cost0) ? cost0 : std::numeric_limits<double>::infinity();
  Recorder recorder(costs, result);
  double a = x0, b = x0;
  if (!bracket(recorder, x0, result.cost, o, result, a, b)) {
    result.ok = true;
    result.message = "no bracket within " + std::to_string(o.max_evaluations) +
                     " evaluations: the best point seen";
    return result;
  }
  if (b - a > o.tolerance) {
    // Brent on x = 1 + (u - a) / (b - a) in [1, 2]: Boost's steps and stopping rule scale with
    // |x| (final bracket about 4 (2^(1-bits) |x| + 2^-1-bits), 5 to 9 x 2^(1-bits) here).
    const double width = b - a;
    const double relative = o.tolerance / width / 7.0;
    const int bits = std::clamp(static_cast<int>(std::ceil(1.0 - std::log2(relative))), 4,
                                std::numeric_limits<double>::digits / 2);
    std::uintmax_t iterations =
        static_cast<std::uintmax_t>(std::max(1, o.max_evaluations - result.evaluations));
    boost::math::tools::brent_find_minima(
        [&](double x) { return recorder.evaluate(a + (x - 1.0) * width); }, 1.0, 2.0, bits,
        iterations);
  }
  result.ok = std::isfinite(result.cost);
  std::ostringstream message;
  message << "bracketed, then Brent's method to a bracket of about " << o.tolerance;
  result.message = result.ok ? message.str() : "no point of the interval could be evaluated";
  return result;
}

}  // namespace identify
}  // namespace flagella
