// Resistive-force-theory drag coefficients of a slender filament (docs/model.md 2).
#pragma once

#include <string>

namespace flagella {

/// Which logarithm the drag coefficients use [CORR-5].
enum class RftLogForm {
  kTwoLengthOverRadius,  ///< ln(2L/r0), Ch.2/3 (Eq. 2.10 / 3.3)
  kLengthOverRadius,     ///< ln(L/r0),  Ch.4 (Eq. 4.17)
};

/// Parses "2L/r0" or "L/r0"; throws std::invalid_argument naming the allowed values.
RftLogForm parseRftLogForm(const std::string& text);
std::string toString(RftLogForm form);

struct RftCoefficients {
  double eta_t = 0.0;  ///< tangential drag per length per speed [N s/m^2]
  double eta_p = 0.0;  ///< normal drag per length per speed [N s/m^2]
};

/// docs/model.md 2: eta_t = 2 pi mu / (ln(arg) - 1/2), eta_p = 4 pi mu / (ln(arg) + 1/2)
RftCoefficients rftCoefficients(double viscosity, double tail_length, double tail_radius,
                                RftLogForm form);

}  // namespace flagella
