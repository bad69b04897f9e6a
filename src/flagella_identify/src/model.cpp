#include "flagella_identify/model.h"

#include <cmath>
#include <sstream>

#include "flagella_sim/core/yaml_fields.h"
#include "flagella_sim/effects/effect_registry.h"

namespace flagella {
namespace identify {

std::vector<double> valuesOf(const std::vector<FitParameter>& parameters) {
  std::vector<double> v;
  for (const FitParameter& p : parameters) v.push_back(p.value);
  return v;
}

namespace {

std::string formatValue(double value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

/// A free parameter "effects.<effect>.<parameter>" of a registered effect: the effect's
/// descriptor and the parameter's schema (both null for any other config path).
struct EffectParameter {
  const EffectDescriptor* effect = nullptr;
  const ParameterSpec* spec = nullptr;
};

EffectParameter effectParameter(const std::string& path) {
  const size_t a = path.find('.'), b = path.find('.', a + 1);
  if (a == std::string::npos || b == std::string::npos || path.substr(0, a) != "effects") return {};
  const EffectDescriptor* d = findEffectDescriptor(path.substr(a + 1, b - a - 1));
  if (!d) return {};
  for (const ParameterSpec& p : d->parameters)
    if (p.name == path.substr(b + 1)) return {d, &p};
  return {};
}

/// The start value of a free parameter: the config's value, or, for a parameter of an effect the
/// config lists without it, the registry default (unless a rule makes that depend on the robot).
double startValue(const YAML::Node& baseline, const std::string& name, const EffectParameter& ep,
                  const std::string& source) {
  const YAML::Node node = configField(baseline, name);
  const YAML::Node effects = baseline["effects"];
  const bool listed = ep.spec && effects.IsMap() && effects[ep.effect->name];
  if (listed && (!node.IsDefined() || node.IsNull())) {
    const std::string rule = ep.effect->defaultRule(ep.spec->name);
    if (!rule.empty())
      throw ConfigError("free parameter '" + name + "' has no value in " + source +
                        " and its default depends on the robot (" + rule +
                        "); give a start value with --set " + name + "=VALUE");
    return ep.spec->value;
  }
  if (!node || !node.IsScalar())
    throw ConfigError("free parameter '" + name + "' is not a number in " + source +
                      " (give a config path such as medium.viscosity or "
                      "effects.stokes_head.C_t)");
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError("free parameter '" + name + "' is not a number in " + source);
  }
}

}  // namespace

YAML::Node configField(const YAML::Node& root, const std::string& path) {
  YAML::Node node = YAML::Clone(root);
  std::stringstream parts(path);
  std::string key;
  while (std::getline(parts, key, '.')) {
    if (!node.IsMap() || !node[key]) return YAML::Node();
    node = node[key];
  }
  return node;
}

Model::Model(YAML::Node baseline, std::string source, const std::vector<std::string>& free,
             double range_factor)
    : baseline_(YAML::Clone(baseline)), source_(std::move(source)) {
  try {
    parseSimulationConfig(baseline_, source_);  // the one validated path; before any fit starts
  } catch (const ConfigError& e) {
    throw ConfigError(source_ + ": " + e.what());
  }
  for (const std::string& name : free) {
    const EffectParameter ep = effectParameter(name);
    const double value = startValue(baseline_, name, ep, source_);
    if (!(value > 0.0) || !std::isfinite(value))
      throw ConfigError("free parameter '" + name + "' must be > 0 in " + source_ +
                        " to be fitted on a log scale, got " + formatValue(value));
    FitParameter p;
    p.name = name;
    p.value = value;
    p.lower = value / range_factor;
    p.upper = value * range_factor;
    if (ep.spec) {  // stay inside the parameter's valid range
      p.lower = std::max(p.lower, std::min(value, ep.spec->min));
      p.upper = std::min(p.upper, std::max(value, ep.spec->max));
      p.unit = ep.spec->unit;
    }
    p.log_scale = true;
    parameters_.push_back(p);
  }
  baseline_count_ = static_cast<int>(parameters_.size());
}

void Model::addCandidate(const Candidate& candidate) {
  candidates_.push_back(&candidate);
  for (const FitParameter& v : candidate.variables) parameters_.push_back(v);
}

void Model::setValues(const std::vector<double>& values) {
  for (size_t i = 0; i < parameters_.size(); ++i) parameters_[i].value = values.at(i);
}

int Model::indexOf(const std::string& name) const {
  for (size_t i = 0; i < parameters_.size(); ++i)
    if (parameters_[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string Model::label() const {
  std::string s = "baseline";
  for (const Candidate* c : candidates_) s += " + " + c->name;
  return s;
}

YAML::Node Model::treeFor(const std::vector<ConfigOverride>& overrides, double session_time,
                          const std::vector<double>& values) const {
  YAML::Node tree = YAML::Clone(baseline_);
  for (const auto& [field, value] : overrides) applyOverride(tree, field + "=" + value);
  for (int i = 0; i < baseline_count_; ++i)
    applyOverride(tree, parameters_[i].name + "=" + formatValue(values.at(i)));
  size_t next = baseline_count_;
  for (const Candidate* c : candidates_) {
    std::vector<double> own(values.begin() + next, values.begin() + next + c->variables.size());
    c->apply(tree, own, session_time);
    next += c->variables.size();
  }
  return tree;
}

SimulationConfig Model::configFor(const std::vector<ConfigOverride>& overrides, double session_time,
                                  const std::vector<double>& values) const {
  return parseSimulationConfig(treeFor(overrides, session_time, values), source_);
}

YAML::Node Model::extendedConfig() const { return treeFor({}, 0.0, values()); }

}  // namespace identify
}  // namespace flagella
