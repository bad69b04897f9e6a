// Chi-square critical values for the selection and the power check (docs/model.md 7.6).
#include "flagella_identify/chi_square.h"

#include <algorithm>

namespace flagella {
namespace identify {

double chiSquareCritical(int k) {
  // chi-square quantiles at p = 1e-3
  static const double table[] = {10.83, 13.82, 16.27, 18.47, 20.52, 22.46};
  return table[std::clamp(k, 1, 6) - 1];
}

}  // namespace identify
}  // namespace flagella
