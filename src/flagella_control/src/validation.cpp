#include "flagella_control/validation.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flagella::control {

std::string numberString(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void requireFinite(const std::string& context, const std::string& field, double value) {
  if (!std::isfinite(value))
    throw std::invalid_argument(context + ": " + field + " must be finite, got " +
                                numberString(value));
}

void requirePositive(const std::string& context, const std::string& field, double value,
                     const std::string& unit) {
  requireFinite(context, field, value);
  if (!(value > 0.0))
    throw std::invalid_argument(context + ": " + field + " must be > 0 " + unit + ", got " +
                                numberString(value));
}

void requireInRange(const std::string& context, const std::string& field, double value, double lo,
                    double hi) {
  if (!(value >= lo && value <= hi))
    throw std::invalid_argument(context + ": " + field + " = " + numberString(value) +
                                " is out of range [" + numberString(lo) + ", " + numberString(hi) +
                                "]");
}

}  // namespace flagella::control
