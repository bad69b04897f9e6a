#include "flagella_sim/effects/effect_registry.h"

#include <sstream>

#include "flagella_sim/core/text_lists.h"

// The descriptor functions, declared from the list itself so that an effect is one line there.
#define FLAGELLA_EFFECT(descriptor)     \
  namespace flagella {                  \
  const EffectDescriptor& descriptor(); \
  }
#include "effect_list.def"
#undef FLAGELLA_EFFECT

namespace flagella {

const std::vector<const EffectDescriptor*>& effectRegistry() {
  static const std::vector<const EffectDescriptor*> table = {
#define FLAGELLA_EFFECT(descriptor) &descriptor(),
#include "effect_list.def"
#undef FLAGELLA_EFFECT
  };
  return table;
}

const EffectDescriptor* findEffectDescriptor(const std::string& name) {
  for (const EffectDescriptor* d : effectRegistry())
    if (d->name == name) return d;
  return nullptr;
}

std::vector<std::string> registeredEffectNames() {
  std::vector<std::string> names;
  for (const EffectDescriptor* d : effectRegistry()) names.push_back(d->name);
  return names;
}

std::string registeredEffectList() { return joined(registeredEffectNames()); }

const EffectDescriptor& effectDescriptor(const std::string& name) {
  if (const EffectDescriptor* d = findEffectDescriptor(name)) return *d;
  throw ConfigError("unknown effect '" + name + "' (known: " + registeredEffectList() + ")");
}

EffectPtr makeEffect(const EffectSpec& spec, const Medium& medium, const RobotDimensions& robot) {
  const EffectDescriptor& descriptor = effectDescriptor(spec.name);
  for (const auto& [a, b] : descriptor.exclusive_parameters)
    if (spec.hasParameter(a) && spec.hasParameter(b))
      throw ConfigError("effects." + spec.name + ": give " + a + " or " + b + ", not both");
  EffectPtr effect = descriptor.make(EffectBuildContext{spec, medium, robot});
  for (const auto& [name, value] : spec.parameters)
    effect->parameters().set(name, value, "effects." + spec.name);
  return effect;
}

namespace {

std::string optionCell(const EffectOption& o) {
  std::string text = "`" + o.name + "`: ";
  if (o.isFlag()) return text + "true/false (default " + o.fallback + "); " + o.description;
  return text + o.choiceList() + " (default " + o.fallback + "); " + o.description;
}

std::string parameterCell(const EffectDescriptor& d, const ParameterSpec& p) {
  const std::string rule = d.defaultRule(p.name);
  std::string text = "`" + p.name + "` [" + formatNumber(p.min) + ", " + formatNumber(p.max) + "]";
  if (!p.unit.empty()) text += " " + p.unit;
  text += ", default " + (rule.empty() ? formatNumber(p.value) : rule);
  return text;
}

std::string discoveryCell(const EffectDescriptor& d) {
  if (!d.discovery) return "-";
  std::string text;
  for (const FittableParameter& v : d.discovery->variables) {
    text += (text.empty() ? "" : ", ") + ("`" + v.variable + "`");
    text += " [" + formatNumber(v.lower) + ", " + formatNumber(v.upper) + "]";
    if (!v.unit.empty()) text += " " + v.unit;
  }
  return text;
}

}  // namespace

std::string effectTableMarkdown() {
  std::ostringstream out;
  out << "| effect | what | options | parameters: range, default | discovery fits |\n"
      << "|---|---|---|---|---|\n";
  for (const EffectDescriptor* d : effectRegistry()) {
    std::string options, parameters;
    for (const EffectOption& o : d->options)
      options += (options.empty() ? "" : "<br>") + optionCell(o);
    for (const ParameterSpec& p : d->parameters)
      parameters += (parameters.empty() ? "" : "<br>") + parameterCell(*d, p);
    out << "| `" << d->name << "` | " << d->description << " | "
        << (options.empty() ? "-" : options) << " | " << parameters << " | " << discoveryCell(*d)
        << " |\n";
  }
  return out.str();
}

}  // namespace flagella
