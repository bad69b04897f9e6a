// The effect registry is the only list of effects: every registered effect round-trips through
// config parsing, the built effect's parameters, `flagella_run params` and `flagella_run effects`
// with the descriptor's ranges; discovery variables lie inside those ranges; the README's effect
// table is the one the registry prints.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/simulation/simulation.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr char kRunExe[] = FLAGELLA_RUN_EXE;
constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;

std::string design1() { return std::string(kConfigDir) + "/granular_design1.yaml"; }

std::string formatValue(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// A value strictly inside [min, max] that differs from the default where possible.
double insideValue(const ParameterSpec& p) {
  const double mid = 0.5 * (p.min + p.max);
  const double geometric = p.min > 0.0 ? std::sqrt(p.min * p.max) : mid;
  return geometric != p.value ? geometric : mid;
}

std::string runTool(const std::string& args) {
  const std::string command = std::string("'") + kRunExe + "' " + args + " 2>&1";
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  ::pclose(pipe);
  return out;
}

TEST(EffectRegistry, NamesAreUniqueAndEveryDescriptorIsComplete) {
  std::set<std::string> names;
  ASSERT_FALSE(effectRegistry().empty());
  for (const EffectDescriptor* d : effectRegistry()) {
    SCOPED_TRACE(d->name);
    EXPECT_TRUE(names.insert(d->name).second) << "registered twice";
    EXPECT_FALSE(d->description.empty());
    EXPECT_EQ(d->description.find('\n'), std::string::npos) << "one line";
    EXPECT_TRUE(static_cast<bool>(d->make));
    for (const ParameterSpec& p : d->parameters) {
      EXPECT_LE(p.min, p.value) << p.name;
      EXPECT_LE(p.value, p.max) << p.name;
      EXPECT_FALSE(p.description.empty()) << p.name;
    }
    for (const auto& [parameter, rule] : d->default_rules) EXPECT_NO_THROW(d->parameter(parameter));
    for (const EffectOption& o : d->options)
      if (!o.isFlag()) {
        EXPECT_NE(std::find(o.allowed.begin(), o.allowed.end(), o.fallback), o.allowed.end());
      }
  }
}

// Each effect alone in design 1 with every parameter at an in-range value: the built effect has
// the descriptor's parameters with the same ranges and units, holding the configured values.
/// True if `name` is the `second` (or, when `second` is false, the first) of an exclusive pair.
bool excludedIn(const EffectDescriptor& d, const std::string& name, bool second) {
  for (const auto& [a, b] : d.exclusive_parameters)
    if (name == (second ? b : a)) return true;
  return false;
}

// Every parameter given at once (one of each exclusive pair, then the other) comes back from the
// built effect with its value, range and unit.
TEST(EffectRegistry, EveryEffectRoundTripsThroughConfigParsing) {
  for (const EffectDescriptor* d : effectRegistry())
    for (bool second : {true, false}) {
      if (!second && d->exclusive_parameters.empty()) continue;
      SCOPED_TRACE(d->name);
      std::vector<std::string> overrides{"effects." + d->name + "={}"};
      std::map<std::string, double> given;
      for (const ParameterSpec& p : d->parameters) {
        if (excludedIn(*d, p.name, second)) continue;
        const double v = insideValue(p);
        given[p.name] = v;
        overrides.push_back("effects." + d->name + "." + p.name + "=" + formatValue(v));
      }
      const SimulationConfig c = loadSimulationConfig(design1(), overrides);
      Simulation sim(c);
      for (const ParameterSpec& p : d->parameters) {
        const ParameterSpec& built = sim.parameterSpec("effects." + d->name + "." + p.name);
        EXPECT_EQ(built.min, p.min) << p.name;
        EXPECT_EQ(built.max, p.max) << p.name;
        EXPECT_EQ(built.unit, p.unit) << p.name;
        if (given.count(p.name)) {
          EXPECT_DOUBLE_EQ(built.value, given[p.name]) << p.name;
        }
      }
      for (const auto& [a, b] : d->exclusive_parameters) {  // both together: named error
        const std::string msg = testing::errorMessageOf<ConfigError>([&] {
          loadSimulationConfig(
              design1(),
              {"effects." + d->name + "." + a + "=" + formatValue(insideValue(d->parameter(a))),
               "effects." + d->name + "." + b + "=" + formatValue(insideValue(d->parameter(b)))});
        });
        EXPECT_NE(msg.find("give " + a + " or " + b + ", not both"), std::string::npos) << msg;
      }
    }
}

// Every parameter just outside its range is a ConfigError that names the field and the range.
TEST(EffectRegistry, OutOfRangeParametersAreRejectedWithTheDescriptorsRange) {
  for (const EffectDescriptor* d : effectRegistry())
    for (const ParameterSpec& p : d->parameters) {
      SCOPED_TRACE(d->name + "." + p.name);
      const double above = p.max + std::max(1.0, std::abs(p.max));
      const std::string field = "effects." + d->name + "." + p.name;
      const std::string msg = testing::errorMessageOf<ConfigError>(
          [&] { loadSimulationConfig(design1(), {field + "=" + formatValue(above)}); });
      EXPECT_NE(msg.find(field), std::string::npos) << msg;
      std::ostringstream range;
      range << "[" << p.min << ", " << p.max << "]";
      EXPECT_NE(msg.find(range.str()), std::string::npos) << msg;
    }
}

TEST(EffectRegistry, OptionsAcceptTheirChoicesAndRejectOthers) {
  for (const EffectDescriptor* d : effectRegistry())
    for (const EffectOption& o : d->options) {
      SCOPED_TRACE(d->name + "." + o.name);
      const std::string field = "effects." + d->name + "." + o.name;
      const std::vector<std::string> values =
          o.isFlag() ? std::vector<std::string>{"true", "false"} : o.allowed;
      for (const std::string& v : values) {
        // an integrated lateral force computes C_yr: the config must not give it
        std::vector<std::string> overrides{field + "=" + v};
        if (d->name == "interface_lateral_force" && v == "integrated")
          overrides.push_back("effects.interface_lateral_force.C_yr=null");
        SimulationConfig c;
        EXPECT_NO_THROW(c = loadSimulationConfig(design1(), overrides)) << v;
        for (const EffectSpec& e : c.effects)
          if (e.name == d->name) {
            EXPECT_EQ(e.option(o.name), v);
          }
      }
      const std::string msg = testing::errorMessageOf<ConfigError>(
          [&] { loadSimulationConfig(design1(), {field + "=no_such_choice"}); });
      EXPECT_NE(msg.find(field), std::string::npos) << msg;
    }
}

TEST(EffectRegistry, DiscoveryVariablesLieInsideTheirParametersRanges) {
  int fittable = 0;
  for (const EffectDescriptor* d : effectRegistry()) {
    if (!d->discovery) continue;
    ++fittable;
    SCOPED_TRACE(d->name);
    const DiscoveryHints& h = *d->discovery;
    EXPECT_FALSE(h.title.empty());
    EXPECT_NE(h.needs, 0u);
    ASSERT_FALSE(h.variables.empty());
    for (const FittableParameter& v : h.variables) {
      const ParameterSpec& p = d->parameter(v.parameter);
      ASSERT_LT(v.lower, v.upper) << v.variable;
      if (v.log_scale) {
        EXPECT_GT(v.lower, 0.0) << v.variable;
      }
      const double a = v.reciprocal ? 1.0 / v.upper : v.lower;
      const double b = v.reciprocal ? 1.0 / v.lower : v.upper;
      EXPECT_GE(a, p.min) << v.variable << " reaches below " << d->name << "." << p.name;
      EXPECT_LE(b, p.max) << v.variable << " reaches above " << d->name << "." << p.name;
    }
    for (const std::vector<double>& start : h.starts) {
      ASSERT_EQ(start.size(), h.variables.size());
      for (size_t i = 0; i < start.size(); ++i) {
        EXPECT_GE(start[i], h.variables[i].lower);
        EXPECT_LE(start[i], h.variables[i].upper);
      }
    }
    for (const TypicalStrength& t : h.typical) {
      bool named = false;
      for (const FittableParameter& v : h.variables) named = named || v.variable == t.variable;
      EXPECT_TRUE(named) << t.variable;
    }
    if (!h.session_time_parameter.empty()) {
      EXPECT_NO_THROW(d->parameter(h.session_time_parameter));
    }
  }
  EXPECT_GT(fittable, 0);
}

// `flagella_run params` with every effect on lists every parameter with the descriptor's range,
// and `flagella_run effects` names every effect; both are read from the same table.
TEST(EffectRegistry, CommandLineListingsShowTheRegistry) {
  const testing::TempDir dir;
  std::string overrides;
  for (const EffectDescriptor* d : effectRegistry())
    overrides += " --set 'effects." + d->name + "={}'";
  const std::string params = runTool("params '" + design1() + "'" + overrides);
  const std::string effects = runTool("effects");
  for (const EffectDescriptor* d : effectRegistry()) {
    SCOPED_TRACE(d->name);
    EXPECT_NE(effects.find(d->name + ": " + d->description), std::string::npos) << effects;
    for (const ParameterSpec& p : d->parameters) {
      const std::string field = "effects." + d->name + "." + p.name;
      const size_t at = params.find(field + " ");
      ASSERT_NE(at, std::string::npos) << params;
      std::istringstream row(params.substr(at, params.find('\n', at) - at));
      std::string name;
      double value = 0.0, min = 0.0, max = 0.0;
      row >> name >> value >> min >> max;
      EXPECT_NEAR(min, p.min, 1e-5 * std::abs(p.min)) << field;
      EXPECT_NEAR(max, p.max, 1e-5 * std::abs(p.max)) << field;
    }
  }
}

// README "Effects" holds exactly the table `flagella_run effects --markdown` prints.
TEST(EffectRegistry, ReadmeTableIsTheRegistrysTable) {
  std::ifstream readme(std::string(kConfigDir) + "/../README.md");
  ASSERT_TRUE(readme.good());
  std::stringstream text;
  text << readme.rdbuf();
  EXPECT_NE(text.str().find(effectTableMarkdown()), std::string::npos)
      << "README.md is out of date; replace its effect table with the output of "
         "`flagella_run effects --markdown`:\n"
      << effectTableMarkdown();
}

}  // namespace
}  // namespace flagella
