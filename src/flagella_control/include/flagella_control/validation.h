// Checks of configuration values for the controller library (calibrations, options, gains):
// each throws std::invalid_argument "<context>: <field> ..." naming the field and what is allowed.
#pragma once

#include <string>

namespace flagella::control {

/// A number as text for messages (shortest stream form).
std::string numberString(double value);

void requireFinite(const std::string& context, const std::string& field, double value);
/// Finite and > 0; `unit` is appended to the message.
void requirePositive(const std::string& context, const std::string& field, double value,
                     const std::string& unit);
/// In [lo, hi] (NaN is out of range).
void requireInRange(const std::string& context, const std::string& field, double value, double lo,
                    double hi);

}  // namespace flagella::control
