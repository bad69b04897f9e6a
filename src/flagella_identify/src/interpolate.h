// Linear interpolation of simulated samples at data times (library-internal).
#pragma once

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace flagella {
namespace identify {

/// Model value at a data time `t`: linear interpolation between the simulated samples at
/// `times`; `member(i)` is the value at sample i.
template <typename Member>
auto interpolateAt(const std::vector<double>& times, double t, Member member) {
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  size_t i = std::min<size_t>(std::max<ptrdiff_t>(it - times.begin(), 1), times.size() - 1);
  const double w = (t - times[i - 1]) / (times[i] - times[i - 1]);
  using Value = std::decay_t<decltype(member(i))>;  // evaluated: no Eigen expression
  return Value(member(i - 1) * (1.0 - w) + member(i) * w);
}

}  // namespace identify
}  // namespace flagella
