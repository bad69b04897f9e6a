#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

const std::string& EffectSpec::option(const std::string& name) const {
  static const std::string kNone;
  for (const auto& [key, value] : options)
    if (key == name) return value;
  return kNone;
}

bool EffectSpec::hasParameter(const std::string& name) const {
  for (const auto& entry : parameters)
    if (entry.first == name) return true;
  return false;
}

const ParameterSpec& EffectDescriptor::parameter(const std::string& name) const {
  for (const ParameterSpec& p : parameters)
    if (p.name == name) return p;
  throw std::logic_error("effect '" + this->name + "' has no parameter '" + name + "'");
}

const EffectOption* EffectDescriptor::findOption(const std::string& option) const {
  for (const EffectOption& o : options)
    if (o.name == option) return &o;
  return nullptr;
}

std::string EffectDescriptor::defaultRule(const std::string& parameter) const {
  for (const auto& [key, rule] : default_rules)
    if (key == parameter) return rule;
  return "";
}

}  // namespace flagella
