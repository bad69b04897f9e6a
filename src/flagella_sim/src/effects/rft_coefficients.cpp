#include "flagella_sim/effects/rft_coefficients.h"

#include <cmath>
#include <stdexcept>

namespace flagella {

RftLogForm parseRftLogForm(const std::string& text) {
  if (text == "2L/r0") return RftLogForm::kTwoLengthOverRadius;
  if (text == "L/r0") return RftLogForm::kLengthOverRadius;
  throw std::invalid_argument("RFT log form '" + text + "' is not one of: 2L/r0, L/r0");
}

std::string toString(RftLogForm form) {
  return form == RftLogForm::kTwoLengthOverRadius ? "2L/r0" : "L/r0";
}

RftCoefficients rftCoefficients(double viscosity, double tail_length, double tail_radius,
                                RftLogForm form) {
  const double ratio =
      (form == RftLogForm::kTwoLengthOverRadius ? 2.0 : 1.0) * tail_length / tail_radius;
  const double log_term = std::log(ratio);
  if (log_term <= 0.5)
    throw std::invalid_argument("RFT needs a slender tail: ln(" + toString(form) +
                                ") = " + std::to_string(log_term) + " must exceed 0.5");
  // docs/model.md 2 (Eq. 2.10/3.3/4.17)
  return {2.0 * M_PI * viscosity / (log_term - 0.5), 4.0 * M_PI * viscosity / (log_term + 0.5)};
}

}  // namespace flagella
