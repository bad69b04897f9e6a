#include "flagella_sim/core/parameter_set.h"

#include <cmath>
#include <sstream>

#include "flagella_sim/core/text_lists.h"

namespace flagella {

std::string rangeMessage(const std::string& field, double value, double min, double max,
                         const std::string& unit) {
  std::ostringstream out;
  out << field << " must be in [" << min << ", " << max << "]";
  if (!unit.empty()) out << " " << unit;
  out << ", got " << value;
  return out.str();
}

void requireInRange(const std::string& field, double value, double min, double max,
                    const std::string& unit) {
  if (!(value >= min && value <= max))
    throw ConfigError(rangeMessage(field, value, min, max, unit));
}

int ParameterSet::declare(const std::string& name, double value, double min, double max,
                          const std::string& unit, const std::string& description) {
  if (has(name)) throw std::logic_error("parameter '" + name + "' declared twice");
  requireInRange(name, value, min, max, unit);
  specs_.push_back({name, value, min, max, unit, description});
  return static_cast<int>(specs_.size()) - 1;
}

int ParameterSet::indexOf(const std::string& name) const {
  for (size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].name == name) return static_cast<int>(i);
  return -1;
}

int ParameterSet::index(const std::string& name) const {
  const int i = indexOf(name);
  if (i < 0) throw std::logic_error("parameter '" + name + "' is not declared");
  return i;
}

bool ParameterSet::has(const std::string& name) const { return indexOf(name) >= 0; }

double ParameterSet::get(const std::string& name) const {
  const int i = indexOf(name);
  if (i < 0) throw ConfigError("unknown parameter '" + abbreviated(name) + "'");
  return specs_[i].value;
}

void ParameterSet::set(const std::string& name, double value, const std::string& context) {
  const int i = indexOf(name);
  // The name may be user text (an unknown key of a config's effect section): quoted short.
  const std::string field = context.empty() ? abbreviated(name) : context + "." + abbreviated(name);
  if (i < 0) {
    std::string known;
    for (const ParameterSpec& s : specs_) known += (known.empty() ? "" : ", ") + s.name;
    throw ConfigError("unknown parameter '" + field + "' (known: " + known + ")");
  }
  const ParameterSpec& s = specs_[i];
  if (!std::isfinite(value) || value < s.min || value > s.max)
    throw ConfigError(rangeMessage(field, value, s.min, s.max, s.unit));
  specs_[i].value = value;
}

}  // namespace flagella
