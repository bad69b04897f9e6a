// Candidates that scale a field of the baseline config by a fitted ratio (field_candidates.h).
#include "field_candidates.h"

#include <cmath>
#include <memory>

#include "flagella_sim/robots/helical_robot.h"

namespace flagella {
namespace identify {

namespace {

/// Bounds of the fitted ratios: a factor of ten either way (docs/model.md 7.6).
constexpr double kLowestRatio = 0.1;
constexpr double kHighestRatio = 10.0;

/// The config path `section[.sub].field` a ratio candidate scales.
struct ScaledField {
  std::string section, sub, field;
  double fallback;  ///< its value when the config does not set it (the parser's default)
  std::string path() const { return section + (sub.empty() ? "" : "." + sub) + "." + field; }
  /// Its value in `config`, or `fallback` where the config does not set it (a missing section
  /// or subsection included: indexing past one would throw YAML::InvalidNode).
  double valueIn(const YAML::Node& config) const {
    const YAML::Node top = config[section];
    if (!top) return fallback;
    const YAML::Node parent = sub.empty() ? top : top[sub];
    if (!parent || !parent[field]) return fallback;
    return parent[field].as<double>();
  }
};

const ScaledField kHookStiffness{"robot", "", "hook_stiffness_scale", 1.0};
const ScaledField kHeadTiltDrag{"effects", "stokes_head", "tilt_drag", 0.0};

/// A one-variable candidate "<name>.ratio" multiplying the baseline's value of `f`, off at 1
/// (the baseline exactly).
Candidate ratioCandidate(const std::string& name, const ScaledField& f) {
  Candidate c;
  c.name = name;
  c.variables = {fitVariable(name + ".ratio", "", kLowestRatio, kHighestRatio, true)};
  c.starts = {{0.5}, {2.0}};
  c.off = {1.0};
  c.steady_table_data = true;
  c.writes = {f.path()};
  c.apply = [f](YAML::Node& cfg, const std::vector<double>& v, double) {
    const double scaled = f.valueIn(cfg) * v[0];
    YAML::Node parent = cfg[f.section];
    if (!f.sub.empty()) parent.reset(parent[f.sub]);
    parent[f.field] = scaled;
  };
  return c;
}

}  // namespace

FitParameter fitVariable(const std::string& name, const std::string& unit, double lower,
                         double upper, bool log_scale) {
  FitParameter p;
  p.name = name;
  p.unit = unit;
  p.lower = lower;
  p.upper = upper;
  p.log_scale = log_scale;
  p.value = log_scale ? std::sqrt(lower * upper) : 0.5 * (lower + upper);
  return p;
}

Candidate hookStiffnessCandidate() {
  Candidate c = ratioCandidate("hook_stiffness", kHookStiffness);
  c.title = "hook stiffer or softer than the flagellum (docs/model.md 8.4.1)";
  c.signature =
      "the flagellum's tilt against the head axis changes with the motor rate, the speed by "
      "a fraction of a percent";
  c.needs = kTranslation | kTilt;
  // a hook of the filament's material 16-26 % thinner (EI, GJ go as r^4); at 0.65 a table
  // of 40-95 rpm with 0.2 deg tilt noise did not show it (held-out RMS z 1.58, docs/model.md 7.6)
  c.typical = {{"hook_stiffness.ratio", 0.3, 0.5, false}};
  c.not_applicable = [](const YAML::Node& baseline) -> std::string {
    const std::shared_ptr<RobotModel> robot = robotOf(baseline);
    if (dynamic_cast<const RobotModelOf<HelicalGeometry>*>(robot.get())) return "";
    return "changes the hook of a helical flagellum, and this robot (robot.type " + robot->type() +
           ") has none";
  };
  return c;
}

Candidate headTiltDragCandidate() {
  Candidate c = ratioCandidate("head_tilt_drag", kHeadTiltDrag);
  c.title = "the head's pitch and yaw drag other than modelled (docs/model.md 3.1)";
  c.signature =
      "the head axis cones less (or more) once per head turn and the track drifts sideways "
      "differently; the flagellum's tilt moves by tenths of a degree";
  // below the threshold a steady table hardly shows it (tilt-drag ratio 3: tilt within 0.3 deg,
  // speed within 0.2 %); a head track's IMU axis and sideways drift move a little more, yet a
  // 40 s track at ratio 2.65 was fitted within its noise (docs/model.md 7.6)
  c.needs = kVertical | kTimeResolved;
  c.steady_table_data = false;
  // a head longer than the sphere of its volume resists pitch and yaw more than spin
  c.typical = {{"head_tilt_drag.ratio", 2.5, 4.0, false}};
  c.not_applicable = [](const YAML::Node& baseline) -> std::string {
    if (kHeadTiltDrag.valueIn(baseline) > 0.0) return "";
    return "scales the head's pitch and yaw drag (effects.stokes_head.tilt_drag), which this "
           "robot's config does not model (absent or 0)";
  };
  return c;
}

}  // namespace identify
}  // namespace flagella
