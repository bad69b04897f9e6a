// Named scalar parameters with allowed ranges. Effects and the medium declare theirs here so
// configs, overrides and the identification tool all address the same numbers by name.
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/core/config_error.h"

namespace flagella {

struct ParameterSpec {
  std::string name;
  double value = 0.0;
  double min = 0.0;
  double max = 0.0;
  std::string unit;
  std::string description;
};

class ParameterSet {
 public:
  /// Declares a parameter and returns its index; the default must lie in [min, max].
  int declare(const std::string& name, double value, double min, double max,
              const std::string& unit, const std::string& description);
  double operator[](int index) const { return specs_[index].value; }
  /// Index of a declared parameter; throws std::logic_error if there is none of that name.
  int index(const std::string& name) const;
  bool has(const std::string& name) const;
  double get(const std::string& name) const;
  /// Sets a value; throws ConfigError naming `context.name` and the range if out of range or
  /// not finite. Never clamps.
  void set(const std::string& name, double value, const std::string& context = "");
  const std::vector<ParameterSpec>& specs() const { return specs_; }

 private:
  int indexOf(const std::string& name) const;
  std::vector<ParameterSpec> specs_;
};

/// "name must be in [min, max] (unit), got value": the one wording every range error uses.
std::string rangeMessage(const std::string& field, double value, double min, double max,
                         const std::string& unit = "");

/// Throws ConfigError with rangeMessage unless min <= value <= max (NaN is never in range).
void requireInRange(const std::string& field, double value, double min, double max,
                    const std::string& unit = "");

}  // namespace flagella
