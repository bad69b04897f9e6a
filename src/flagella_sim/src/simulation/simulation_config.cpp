#include "flagella_sim/simulation/simulation_config.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>

#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/core/yaml_fields.h"
#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/simulation/problem_size.h"

namespace flagella {

namespace {

constexpr double kMaxMotorRpm = 1e4;

// robot.type names the type (robot_registry.h); its descriptor reads the other fields.
void parseRobot(FieldReader r, SimulationConfig& c) {
  RobotHeadSize head;
  c.robot = parseRobotSection(r, head);
  c.head_radius = head.radius;
  c.head_length = head.length;
}

void parseMedium(FieldReader r, SimulationConfig& c) {
  c.medium.parameters().set("viscosity", r.number("viscosity", 1.0, 0.0, 1e6, "Pa s"), r.path());
  c.medium.parameters().set("density", r.number("density", 1000.0, 0.0, 1e5, "kg/m^3"), r.path());
  const Vec3 up = r.vector3("up", Vec3::UnitZ());
  if (up.norm() < 1e-9) throw ConfigError(r.field("up") + " must be a non-zero vector");
  c.medium.up = up.normalized();
  c.medium.gravity = r.vector3("gravity", -9.81 * c.medium.up);
  FieldReader p = r.child("interface_profile");
  InterfaceViscosityProfile& prof = c.medium.profile;
  prof.enabled = p.flag("enabled", false);
  prof.reference_height = p.number("reference_height", 0.0, -100.0, 100.0, "m");
  prof.length_scale = p.number("length_scale", c.head_radius, 1e-5, 10.0, "m");
  prof.onset_height = p.number("onset_height", 0.7 * prof.length_scale, -10.0, 10.0, "m");
  prof.sharpness = p.number("sharpness", 20.0, 0.0, 1e4);
  p.rejectUnknown();
  r.rejectUnknown();
}

// A key without a value under an effect (`bogus:`, or a decimal comma in a flow map such as
// `{C_t: 1,5}`) is refused like a key with one.
void requireKnownParameter(const EffectDescriptor& d, const std::string& key,
                           const std::string& field) {
  std::string known;
  for (const ParameterSpec& p : d.parameters) {
    if (p.name == key) return;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  throw ConfigError("unknown parameter '" + field + "' without a value (known: " + known + ")");
}

// The effect's descriptor gives its schema: structural options first, every remaining field
// is a named parameter (its range is checked when the effect is built, see makeEffect).
EffectSpec parseEffect(FieldReader r, const EffectDescriptor& d) {
  EffectSpec e;
  e.name = d.name;
  for (const EffectOption& o : d.options) {
    const std::string value = o.isFlag() ? (r.flag(o.name, o.fallback == "true") ? "true" : "false")
                                         : r.choice(o.name, o.fallback, o.allowed);
    e.options.emplace_back(o.name, value);
  }
  constexpr double kAnyFinite = std::numeric_limits<double>::max();
  for (const std::string& key : r.keys()) {
    if (d.findOption(key)) continue;
    if (!r.has(key)) {  // null: the default of a known parameter; an unknown key is refused
      requireKnownParameter(d, key, r.field(key));
      continue;
    }
    e.parameters.emplace_back(key, r.number(key, 0.0, -kAnyFinite, kAnyFinite));
  }
  return e;
}

void parseEffects(FieldReader r, SimulationConfig& c) {
  for (const std::string& name : r.keys()) {
    const EffectDescriptor* d = findEffectDescriptor(name);
    if (!d)
      throw ConfigError("unknown effect '" + r.field(name) + "' (known: " + registeredEffectList() +
                        ")");
    c.effects.push_back(parseEffect(r.child(name), *d));
  }
}

void parseMotor(FieldReader r, SimulationConfig& c) {
  MotorSpec& m = c.motor;
  m.mode = r.choice("mode", "constant", {"constant", "binary"});
  m.omega =
      r.number("omega_rpm", 0.0, -kMaxMotorRpm, kMaxMotorRpm, "rpm") * units::kRadPerSecPerRpm;
  m.ramp_time = r.number("ramp_time", 0.0, 0.0, 1e4, "s");
  if (m.mode == "binary") {
    m.positive_duration = r.number("positive_duration", 1.0, 1e-6, 1e6, "s");
    m.negative_duration = r.number("negative_duration", m.positive_duration, 1e-6, 1e6, "s");
  } else {
    for (const char* key : {"positive_duration", "negative_duration"})
      if (r.has(key))
        throw ConfigError(r.field(key) + " applies only to " + r.field("mode") + ": binary (" +
                          r.field("mode") + " is " + m.mode +
                          (r.has("mode") ? "" : ", the default, as it is not given or null") + ")");
  }
  r.rejectUnknown();
}

void parseSlider(FieldReader r, SimulationConfig& c) {
  using namespace slider_limits;
  SliderSpec& s = c.slider;
  s.enabled = true;
  s.mass = r.number("mass", s.mass, kMinMass, kMaxMass, "kg");
  s.lead = r.number("lead", s.lead, kMinLead, kMaxLead, "m");
  s.max_screw_rate = units::rpmToRadPerSec(
      r.number("max_screw_rpm", units::radPerSecToRpm(s.max_screw_rate),
               units::radPerSecToRpm(kMinScrewRate), units::radPerSecToRpm(kMaxScrewRate), "rpm"));
  s.max_screw_accel =
      r.number("max_screw_accel", s.max_screw_accel, kMinScrewAccel, kMaxScrewAccel, "rad/s^2");
  s.travel_min = r.number("travel_min", s.travel_min, -kMaxTravel, 0.0, "m");
  s.travel_max = r.number("travel_max", s.travel_max, 0.0, kMaxTravel, "m");
  s.initial_position =
      r.number("initial_position", s.initial_position, -kMaxTravel, kMaxTravel, "m");
  r.rejectUnknown();
  s.validate();
  if (!c.effect(ComOffset::kName))
    throw ConfigError(r.path() +
                      " needs effects.com_offset: the slider shifts that couple's offset l");
}

void parseSimulation(FieldReader r, SimulationConfig& c) {
  c.dt = r.number("dt", 0.01, 1e-7, 1.0, "s");
  c.duration = r.number("duration", 10.0, 0.0, 1e6, "s");
  c.output_interval = r.number("output_interval", std::max(c.dt, 0.1), 1e-7, 1e6, "s");
  if (c.output_interval < c.dt)  // outputs come at whole steps
    throw ConfigError(r.field("output_interval") + " (" + formatNumber(c.output_interval) +
                      " s) must be at least " + r.field("dt") + " (" + formatNumber(c.dt) +
                      " s): outputs come at whole steps; raise it or lower dt");
  c.steady_fraction = r.number("steady_fraction", 0.5, 0.01, 1.0);
  c.buckling_tilt_deg = r.number("buckling_tilt_deg", c.buckling_tilt_deg, 0.0, 90.0, "deg");
  if (c.buckling_tilt_deg <= 0.0 || c.buckling_tilt_deg >= 90.0)
    throw ConfigError(r.field("buckling_tilt_deg") + " must be in (0, 90) deg, got " +
                      formatNumber(c.buckling_tilt_deg));
  r.rejectUnknown();
}

void parseSolver(FieldReader r, SimulationConfig& c) {
  NewtonOptions& o = c.solver;
  // Lower bound: the shipped robots converge down to 1e-11; at 1e-12 round-off stalls Newton
  // (interface robot: scaled residual 1.4e-9 after 6 subdivisions), so 1e-10 leaves a margin.
  o.residual_tolerance = r.number("residual_tolerance", o.residual_tolerance, 1e-10, 1.0);
  o.step_tolerance = r.number("step_tolerance", o.step_tolerance, 0.0, 1e-3);
  o.max_iterations = r.integer("max_iterations", o.max_iterations, 1, 1000);
  o.damped_retry = r.flag("damped_retry", o.damped_retry);
  o.stagnation_updates =
      r.integer("stagnation_updates", o.stagnation_updates, NewtonOptions::kMinStagnationUpdates,
                NewtonOptions::kMaxStagnationUpdates);
  o.max_subdivision_depth = r.integer("max_subdivision_depth", o.max_subdivision_depth, 0, 20);
  o.jacobian_reuse = r.number("jacobian_reuse", o.jacobian_reuse, 0.0, 1.0);
  o.krylov_iterations = r.integer("krylov_iterations", o.krylov_iterations, 0, 200);
  o.extrapolate_initial_guess = r.flag("extrapolate_initial_guess", o.extrapolate_initial_guess);
  o.rotating_predictor = r.choice("predictor", "linear", {"linear", "rotating"}) == "rotating";
  o.block_lu = r.choice("linear_solver", "block_lu", {"block_lu", "klu"}) == "block_lu";
  o.condensed_dense_lu =
      r.choice("dense_solver", "condensed", {"condensed", "full"}) == "condensed";
  o.trace = r.flag("trace", o.trace);
  c.size_check = r.flag("size_check", c.size_check);
  r.rejectUnknown();
  // Scale-aware convergence test (docs/model.md 1.10): forces against EI/L^2, moments against EI/L.
  const double EI = c.robot->filament().EI();
  const double L = c.robot->filamentLength();
  o.force_scale = EI / (L * L);
  o.moment_scale = EI / L;
  o.length_scale = L;
}

}  // namespace

RobotDimensions SimulationConfig::robotDimensions() const {
  RobotDimensions d;
  d.head_radius = head_radius;
  d.head_length = head_length;
  const RodMaterial& filament = robot->filament();
  d.body_density = filament.density;
  d.filament_radius = filament.radius;
  return d;
}

SimulationConfig parseSimulationConfig(const YAML::Node& root, const std::string& source) {
  SimulationConfig c;
  c.source = source;
  FieldReader top(root, "");
  parseRobot(top.child("robot"), c);
  parseMedium(top.child("medium"), c);
  parseEffects(top.child("effects"), c);
  parseMotor(top.child("motor"), c);
  if (top.has("slider")) parseSlider(top.child("slider"), c);
  parseSimulation(top.child("simulation"), c);
  parseSolver(top.child("solver"), c);
  top.rejectUnknown();
  const RobotDimensions robot = c.robotDimensions();
  for (const EffectSpec& spec : c.effects) makeEffect(spec, c.medium, robot);  // validates values
  requireRunnableSize(c);
  return c;
}

YAML::Node loadConfigTree(const std::string& path, const std::vector<std::string>& overrides) {
  YAML::Node root = loadStrictYamlFile(path, "config");
  try {
    for (const std::string& o : overrides) applyOverride(root, o);
  } catch (const ConfigError& e) {
    throw ConfigError(path + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw ConfigError(path + ": " + e.what());
  }
  return root;
}

namespace {

bool isNamePart(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
}

// Where `field` occurs in `message` as a whole dotted name (not a prefix of a longer one).
size_t findWholeName(const std::string& message, const std::string& field) {
  for (size_t at = message.find(field); at != std::string::npos; at = message.find(field, at + 1)) {
    const size_t end = at + field.size();
    if ((at == 0 || !isNamePart(message[at - 1])) &&
        (end == message.size() || !isNamePart(message[end]) ||
         (message[end] == '.' && (end + 1 == message.size() || !isNamePart(message[end + 1])))))
      return at;
  }
  return std::string::npos;
}

// The source to blame for an error about a field: the last override that set it (a --set
// value, a launch argument), else the file. Field errors start with the field's dotted name;
// an error that names an overridden field elsewhere (an unknown field, a rule between two
// fields such as pitch > 2 filament_radius) blames that override too.
std::string sourceOf(const std::string& message, const std::string& path,
                     const std::vector<std::string>& overrides) {
  const std::string* named = nullptr;
  for (auto o = overrides.rbegin(); o != overrides.rend(); ++o) {
    const std::string field = o->substr(0, o->find('='));
    if (field.empty()) continue;
    const size_t at = findWholeName(message, field);
    if (at == 0) return "override '" + abbreviated(*o) + "' (on " + path + ")";
    if (at != std::string::npos && !named) named = &*o;
  }
  if (named) return "override '" + abbreviated(*named) + "' (on " + path + ")";
  return path;
}

}  // namespace

SimulationConfig loadSimulationConfig(const std::string& path,
                                      const std::vector<std::string>& overrides) {
  const YAML::Node root = loadConfigTree(path, overrides);
  try {
    return parseSimulationConfig(root, path);
  } catch (const ConfigError& e) {
    throw ConfigError(sourceOf(e.what(), path, overrides) + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw ConfigError(path + ": " + e.what());
  }
}

}  // namespace flagella
