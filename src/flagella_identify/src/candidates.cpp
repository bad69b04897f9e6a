#include "flagella_identify/candidates.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {
namespace identify {

namespace {

FitParameter variable(const std::string& name, const std::string& unit, double lower, double upper,
                      bool log_scale) {
  FitParameter p;
  p.name = name;
  p.unit = unit;
  p.lower = lower;
  p.upper = upper;
  p.log_scale = log_scale;
  p.value = log_scale ? std::sqrt(lower * upper) : 0.5 * (lower + upper);
  return p;
}

/// Switches an effect on (an empty map if it has no fields yet) and sets its fields.
void setEffect(YAML::Node& config, const std::string& effect,
               const std::vector<std::pair<std::string, double>>& fields) {
  YAML::Node effects = config["effects"];
  if (!effects[effect] || !effects[effect].IsMap())
    effects[effect] = YAML::Node(YAML::NodeType::Map);
  for (const auto& [key, value] : fields) effects[effect][key] = value;
}

int tailCount(const YAML::Node& config) {
  const YAML::Node n = config["robot"]["n_tails"];
  return n ? n.as<int>() : 2;  // MultiTailGeometry's default
}

std::vector<Candidate> makeCandidates() {
  std::vector<Candidate> list;
  {
    Candidate c;
    c.name = "interface_lateral_force";
    c.title = "depth-dependent viscosity near an interface (lateral head force)";
    c.signature = "circling: a steady yaw rate that reverses with the sign of rotation";
    c.needs = kHeading;
    c.variables = {variable("interface_lateral_force.C_yr", "", -50.0, 50.0, false)};
    c.starts = {{-1e-1}, {-1e-2}, {-1e-3}, {1e-3}, {1e-2}, {1e-1}};  // both signs, three decades
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      setEffect(cfg, "interface_lateral_force", {{"C_yr", v[0]}});  // spec 3.3, Eq. 4.13
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "granular_yield";
    c.title = "granular yield threshold";
    c.signature = "threshold: no translation below a motor speed, full speed above it";
    c.needs = kTranslation;
    c.variables = {variable("granular_yield.yield_force", "N", 1e-7, 1.0, true)};
    c.starts = {{1e-5}, {1e-4}, {1e-3}};
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      setEffect(cfg, "granular_yield", {{"yield_force", v[0]}});
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "granular_jamming";
    c.title = "granular stick-slip (jamming and release)";
    c.signature = "intermittency: the head slows to a stop while resistance builds, then surges";
    c.needs = kTranslation | kTimeResolved;
    c.variables = {variable("granular_jamming.stiffness", "N/m", 1e-4, 1e3, true),
                   variable("granular_jamming.release_force", "N", 1e-7, 1.0, true)};
    // A grid: the fit of a stick-slip is multimodal. Whether the head stops at a command depends
    // on F_r against the thrust there, so the training cost has a narrow valley in F_r: steps of
    // 10^0.1 (26 %) resolve commands whose thrusts differ by 1.3-2x. Release distances
    // s_r = F_r/k_j of 0.3, 1 and 3 mm.
    for (int i = 0; i <= 12; ++i) {
      const double release = 2.5e-4 * std::pow(10.0, 0.1 * i);  // 0.25-4 mN
      for (double distance : {3e-4, 1e-3, 3e-3}) c.starts.push_back({release / distance, release});
    }
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      setEffect(cfg, "granular_jamming", {{"stiffness", v[0]}, {"release_force", v[1]}});
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "dc_motor";
    c.title = "DC-motor torque-speed curve";
    c.signature =
        "saturation: head plus tail spin falls short of the commanded motor speed, "
        "more so under load";
    c.needs = kRotation;
    c.variables = {variable("dc_motor.inverse_stall_torque", "1/(N m)", 1e-2, 1e6, true)};
    c.starts = {{30.0}, {300.0}, {3000.0}};
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      setEffect(cfg, "dc_motor", {{"stall_torque", 1.0 / v[0]}});
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "com_offset";
    c.title = "centre-of-mass offset with gravity and buoyancy";
    c.signature = "drift in pitch: the head axis tilts and the path climbs or dives";
    c.needs = kVertical | kTimeResolved;
    c.variables = {variable("com_offset.offset", "m", -0.05, 0.05, false)};
    c.starts = {{-2e-3}, {2e-3}};
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      setEffect(cfg, "com_offset", {{"offset", v[0]}});  // spec 5
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "fabrication_asymmetry";
    c.title = "fabrication asymmetry (tail 1 shorter or stiffer than the others)";
    c.signature = "asymmetry: a sideways wobble at the tail rotation rate and a curved path";
    c.needs = kTranslation | kTimeResolved;
    c.variables = {variable("fabrication_asymmetry.length_ratio", "", 0.5, 1.5, true),
                   variable("fabrication_asymmetry.stiffness_ratio", "", 0.2, 5.0, true)};
    c.starts = {{0.85, 1.0}, {1.0, 1.6}, {1.0, 0.6}};
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double) {
      const int n = tailCount(cfg);
      YAML::Node length(YAML::NodeType::Sequence), stiffness(YAML::NodeType::Sequence);
      for (int k = 0; k < n; ++k) {
        length.push_back(k == 0 ? v[0] : 1.0);
        stiffness.push_back(k == 0 ? v[1] : 1.0);
      }
      cfg["robot"]["tail_length_scale"] = length;
      cfg["robot"]["tail_stiffness_scale"] = stiffness;
    };
    list.push_back(c);
  }
  {
    Candidate c;
    c.name = "viscosity_drift";
    c.title = "slow viscosity drift with temperature";
    c.signature = "drift: the same experiment gives different speeds at different session times";
    c.needs = kSessionTime;
    c.variables = {variable("viscosity_drift.rate", "1/h", -2.0, 2.0, false)};
    c.starts = {{-0.1}, {0.1}};
    c.apply = [](YAML::Node& cfg, const std::vector<double>& v, double session_time) {
      setEffect(cfg, "viscosity_drift", {{"rate", v[0]}, {"session_time", session_time}});
    };
    list.push_back(c);
  }
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
    default:
      return "?";
  }
}

/// Experiments that span less than this are treated as taken at one session time [s].
constexpr double kMinSessionSpread = 600.0;

}  // namespace

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

std::string notIdentifiableReason(const Candidate& c, unsigned observables) {
  std::string missing;
  for (unsigned bit = 1; bit <= kSessionTime; bit <<= 1)
    if ((c.needs & bit) && !(observables & bit))
      missing += std::string(missing.empty() ? "" : "; ") + observableName(bit);
  return missing.empty() ? "" : "needs " + missing;
}

}  // namespace identify
}  // namespace flagella
