#include "flagella_identify/candidates.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "field_candidates.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/robots/robot_registry.h"

namespace flagella {
namespace identify {

namespace {

/// Switches an effect on (an empty map if it has no fields yet) and sets its fields.
void setEffect(YAML::Node& config, const std::string& effect,
               const std::vector<std::pair<std::string, double>>& fields) {
  YAML::Node effects = config["effects"];
  if (!effects[effect] || !effects[effect].IsMap())
    effects[effect] = YAML::Node(YAML::NodeType::Map);
  for (const auto& [key, value] : fields) effects[effect][key] = value;
}

/// The candidate of a registered effect: its descriptor's fittable parameters, named
/// "<effect>.<variable>", written into the effect's config section.
Candidate effectCandidate(const EffectDescriptor& d) {
  const DiscoveryHints& h = *d.discovery;
  Candidate c;
  c.name = d.name;
  c.title = h.title;
  c.signature = h.signature;
  c.needs = h.needs;
  for (const FittableParameter& v : h.variables) {
    c.variables.push_back(
        fitVariable(d.name + "." + v.variable, v.unit, v.lower, v.upper, v.log_scale));
    c.off.push_back(v.off);
  }
  c.starts = h.starts;
  c.writes = {"effects." + d.name};
  c.apply = [&d](YAML::Node& cfg, const std::vector<double>& values, double session_time) {
    const DiscoveryHints& hints = *d.discovery;
    std::vector<std::pair<std::string, double>> fields;
    for (size_t i = 0; i < hints.variables.size(); ++i) {
      const FittableParameter& v = hints.variables[i];
      fields.emplace_back(v.parameter, v.reciprocal ? 1.0 / values[i] : values[i]);
    }
    if (!hints.session_time_parameter.empty())
      fields.emplace_back(hints.session_time_parameter, session_time);
    setEffect(cfg, d.name, fields);
  };
  for (TypicalStrength t : h.typical) {
    t.variable = d.name + "." + t.variable;
    c.typical.push_back(t);
  }
  for (TypicalStrength t : h.typical_single_flagellum) {
    t.variable = d.name + "." + t.variable;
    c.typical_single_flagellum.push_back(t);
  }
  c.steady_table_data = h.steady_table_data;
  if (!h.requires_effect.empty())
    c.not_applicable = [&d](const YAML::Node& baseline) -> std::string {
      const DiscoveryHints& hints = *d.discovery;
      if (baseline["effects"] && baseline["effects"][hints.requires_effect]) return "";
      return "acts only with " + hints.requires_what + " (effects." + hints.requires_effect +
             "), which this robot's config does not have";
    };
  return c;
}

/// A candidate that is not an effect: tail 1 shorter or stiffer than the others (robot fields
/// tail_length_scale, tail_stiffness_scale).
Candidate fabricationAsymmetryCandidate() {
  Candidate c;
  c.name = "fabrication_asymmetry";
  c.title = "fabrication asymmetry (tail 1 shorter or stiffer than the others)";
  c.signature = "asymmetry: a sideways wobble at the tail rotation rate and a curved path";
  c.needs = kTranslation | kTimeResolved;
  c.variables = {fitVariable("fabrication_asymmetry.length_ratio", "", 0.5, 1.5, true),
                 fitVariable("fabrication_asymmetry.stiffness_ratio", "", 0.2, 5.0, true)};
  c.starts = {{0.85, 1.0}, {1.0, 1.6}, {1.0, 0.6}};
  c.off = {1.0, 1.0};  // every tail alike: the baseline robot
  c.writes = {"robot.tail_length_scale", "robot.tail_stiffness_scale"};
  c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
    const int n = tailCountOf(cfg);
    YAML::Node length(YAML::NodeType::Sequence), stiffness(YAML::NodeType::Sequence);
    for (int k = 0; k < n; ++k) {
      length.push_back(k == 0 ? v[0] : 1.0);
      stiffness.push_back(k == 0 ? v[1] : 1.0);
    }
    cfg["robot"]["tail_length_scale"] = length;
    cfg["robot"]["tail_stiffness_scale"] = stiffness;
  };
  c.steady_table_data = false;
  c.not_applicable = [](const YAML::Node& baseline) -> std::string {
    if (!isSingleFlagellum(baseline)) return "";
    return "makes tail 1 differ from the others, and this robot has " +
           std::to_string(tailCountOf(baseline)) + " tail";
  };
  return c;
}

/// `c` whose `apply` leaves the config alone at the off values, so that the nested model there
/// is the simpler one exactly (Candidate::off).
Candidate leavingOutWhenOff(Candidate c) {
  c.apply = [apply = c.apply, off = c.off](YAML::Node& config, const std::vector<double>& values,
                                           double session_time) {
    if (values == off) return;
    apply(config, values, session_time);
  };
  return c;
}

std::vector<Candidate> makeCandidates() {
  std::vector<Candidate> list;
  for (const EffectDescriptor* d : effectRegistry())
    if (d->discovery) list.push_back(leavingOutWhenOff(effectCandidate(*d)));
  list.push_back(leavingOutWhenOff(fabricationAsymmetryCandidate()));
  list.push_back(leavingOutWhenOff(hookStiffnessCandidate()));
  list.push_back(leavingOutWhenOff(headTiltDragCandidate()));
  return list;
}

const char* observableName(unsigned o) {
  switch (o) {
    case kTranslation:
      return "head translation (v or positions)";
    case kRotation:
      return "rotation rates or counted turns";
    case kHeading:
      return "heading (omega_yr, R_yr or a horizontal path)";
    case kVertical:
      return "vertical position or orientation over time";
    case kTimeResolved:
      return "a time series";
    case kSessionTime:
      return "experiments spread over the session (time_s or session_time_s)";
    case kTilt:
      return "the flagellum's tilt (tilt_deg)";
    default:
      return "?";
  }
}

/// Experiments that span less than this are treated as taken at one session time [s].
constexpr double kMinSessionSpread = 600.0;

}  // namespace

std::shared_ptr<RobotModel> robotOf(const YAML::Node& config) {
  // only the robot section is read (the model run parses the whole config once more anyway)
  FieldReader robot(config["robot"], "robot");
  RobotHeadSize head;
  return parseRobotSection(robot, head);
}

int tailCountOf(const YAML::Node& config) { return robotOf(config)->tailCount(); }

bool isSingleFlagellum(const YAML::Node& config) { return tailCountOf(config) < 2; }

unsigned observablesOf(const MeasuredData& data) {
  unsigned o = 0;
  double first = 1e300, last = -1e300;
  auto seen = [&](double t) {
    if (!std::isfinite(t)) return;
    first = std::min(first, t);
    last = std::max(last, t);
  };
  for (const SteadyStateTable& table : data.tables)
    for (const SteadyStateRow& row : table.rows) {
      for (const auto& [name, value] : row.measured) {
        if (!std::isfinite(value)) continue;
        if (name == "v") o |= kTranslation;
        if (name == "omega_h" || name == "omega_t") o |= kRotation;
        if (name == "omega_yr" || name == "R_yr") o |= kHeading;
        if (name == "tilt") o |= kTilt;
      }
      seen(row.time);
    }
  for (const TimeSeries& s : data.series) {
    o |= kTranslation | kHeading | kTimeResolved;
    if (s.has_z || !s.orientation.empty()) o |= kVertical;
    if (!s.head_turns.empty() || !s.tail_turns.empty()) o |= kRotation;
    seen(s.session_time);
    seen(s.session_time + (s.t.back() - s.t.front()));
  }
  if (last - first >= kMinSessionSpread) o |= kSessionTime;
  return o;
}

const std::vector<Candidate>& standardCandidates() {
  static const std::vector<Candidate> list = makeCandidates();
  return list;
}

const Candidate& candidateByName(const std::string& name) {
  for (const Candidate& c : standardCandidates())
    if (c.name == name) return c;
  std::ostringstream s;
  s << "unknown candidate effect '" << name << "'; known:";
  for (const Candidate& c : standardCandidates()) s << " " << c.name;
  throw ConfigError(s.str());
}

std::vector<const Candidate*> candidatesNamed(const std::vector<std::string>& names) {
  std::vector<const Candidate*> pool;
  if (names.empty())
    for (const Candidate& c : standardCandidates()) pool.push_back(&c);
  for (const std::string& name : names) pool.push_back(&candidateByName(name));
  return pool;
}

std::string notIdentifiableReason(const Candidate& c, unsigned observables) {
  std::string missing;
  for (unsigned bit = 1; bit <= kLastObservable; bit <<= 1)
    if ((c.needs & bit) && !(observables & bit))
      missing += std::string(missing.empty() ? "" : "; ") + observableName(bit);
  return missing.empty() ? "" : "needs " + missing;
}

const std::vector<TypicalStrength>& typicalStrengths(const Candidate& c,
                                                     const YAML::Node& baseline) {
  if (!c.typical_single_flagellum.empty() && isSingleFlagellum(baseline))
    return c.typical_single_flagellum;
  return c.typical;
}

std::string notApplicableReason(const Candidate& c, const YAML::Node& baseline) {
  return c.not_applicable ? c.not_applicable(baseline) : "";
}

}  // namespace identify
}  // namespace flagella
