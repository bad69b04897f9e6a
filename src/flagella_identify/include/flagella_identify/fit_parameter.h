// One number an identification fit may change: a config field of the baseline robot
// ("medium.viscosity", "effects.stokes_head.C_t") or a variable of a candidate effect.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace flagella {
namespace identify {

struct FitParameter {
  std::string name;  ///< config path ("medium.viscosity") or "<candidate>.<variable>"
  std::string unit;
  double value = 0.0;  ///< start value before a fit, fitted value after
  double lower = 0.0;  ///< allowed range (the fit never leaves it)
  double upper = 0.0;
  bool log_scale = false;  ///< fitted as log(value): positive, spans decades
  double uncertainty = std::numeric_limits<double>::quiet_NaN();  ///< one standard deviation
};

/// Values of a parameter list, in order.
std::vector<double> valuesOf(const std::vector<FitParameter>& parameters);

}  // namespace identify
}  // namespace flagella
