// The helical robot type (docs/model.md 8.4): its config section and what the rest of the
// product asks of it (robot_model.h).
#include <cstdio>

#include "flagella_sim/core/config_error.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/robots/flagellum_tilt.h"
#include "flagella_sim/robots/helical_robot.h"
#include "flagella_sim/robots/robot_registry.h"

namespace flagella {

namespace {

class HelicalRobotModel : public RobotModelOf<HelicalGeometry> {
 public:
  using RobotModelOf::RobotModelOf;
  const std::string& type() const override {
    static const std::string name = "helical";
    return name;
  }
  RodNetwork build() const override { return buildHelicalRobot(geometry); }
  const RodMaterial& filament() const override { return geometry.flagellum; }
  double filamentLength() const override { return geometry.axialLength(); }
  int tailCount() const override { return 1; }
  std::string label() const override {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "helical, %g pitches", geometry.pitch_count);
    return buf;
  }
  // docs/model.md 8.4: the helix that replaces n_tails and tail_length in the summary.
  std::vector<SummaryField> summaryFields() const override {
    const HelicalGeometry& g = geometry;
    return {{"robot", std::string("helical")},
            {"pitch_count", g.pitch_count},
            {"pitch_m", g.pitch},
            {"helix_radius_m", g.helix_radius},
            {"axial_length_m", g.axialLength()},
            {"filament_radius_m", g.flagellum.radius},
            {"handedness", std::string(g.handedness == kLeftHanded ? "left" : "right")},
            {"mount", std::string(g.mount == HelicalMount::kGimbal ? "gimbal" : "untethered")}};
  }
  // docs/model.md 8.4.4
  std::optional<double> flagellumTilt(const VecX& q, const RobotParts& parts,
                                      const Vec3& head_axis) const override {
    return flagella::flagellumTilt(q, helixNodes(parts), geometry.edgesPerTurn(), head_axis);
  }
  bool hasFlagellumTilt() const override { return true; }
  std::shared_ptr<RobotModel> clone() const override {
    return std::make_shared<HelicalRobotModel>(*this);
  }
};

// robot.pitch_count or robot.axial_length (exclusive) sets L_t / lambda.
void parseHelixLength(FieldReader& r, HelicalGeometry& g) {
  if (r.has("pitch_count") && r.has("axial_length"))
    throw ConfigError(r.field("pitch_count") + " and " + r.field("axial_length") +
                      " are exclusive: give one");
  g.pitch_count = r.number("pitch_count", g.pitch_count, kMinPitchCount, kMaxPitchCount);
  if (r.has("axial_length")) {
    const double L_t = r.number("axial_length", g.axialLength(), 1e-5, 500.0, "m");
    requireInRange(r.field("axial_length") + " (0.5 to 50 pitches)", L_t, kMinPitchCount * g.pitch,
                   kMaxPitchCount * g.pitch, "m");
    g.pitch_count = L_t / g.pitch;
  } else {
    r.describe("axial_length", "", "0.5 to 50 pitches, instead of pitch_count", "m");
  }
}

// docs/model.md 8.4; defaults (HelicalGeometry): the Shore 32 VPS robot with 3.5 pitches.
std::shared_ptr<RobotModel> parseHelicalRobot(FieldReader& r, RobotHeadSize& head) {
  HelicalGeometry g;
  g.helix_radius = r.number("helix_radius", g.helix_radius, 1e-5, 10.0, "m");
  g.pitch = r.number("pitch", g.pitch, 1e-5, 10.0, "m");
  parseHelixLength(r, g);
  g.flagellum.radius = r.number("filament_radius", g.flagellum.radius, 1e-6, 0.1, "m");
  g.flagellum.youngs_modulus =
      r.number("youngs_modulus", g.flagellum.youngs_modulus, 1.0, 1e12, "Pa");
  g.flagellum.poisson_ratio = r.number("poisson_ratio", g.flagellum.poisson_ratio, 0.0, 0.5);
  g.flagellum.density = r.number("density", g.flagellum.density, 1.0, 1e5, "kg/m^3");
  g.edge_length = r.number("edge_length", g.edge_length, 1e-5, 1.0, "m");
  g.head_radius = r.number("head_radius", g.head_radius, 1e-4, 1.0, "m");
  g.hook_length = r.number("hook_length", g.hook_length, 0.0, 10.0, "m");
  g.handedness =
      r.choice("handedness", "left", {"left", "right"}) == "left" ? kLeftHanded : kRightHanded;
  g.mount = r.choice("mount", "untethered", {"untethered", "gimbal"}) == "gimbal"
                ? HelicalMount::kGimbal
                : HelicalMount::kUntethered;
  g.rigid_factor = r.number("rigid_factor", g.rigid_factor, 1.0, 1e6);
  g.hook_stiffness_scale = r.number("hook_stiffness_scale", g.hook_stiffness_scale, 0.01, 100.0);
  validateHelicalGeometry(g);  // cross-field checks: self-intersection, hook, edge count
  // docs/model.md 5, 8.4.1: R_H is the sphere-equivalent radius, so the head volume
  // pi a^2 L_head = 4/3 pi R_H^3 with a = R_H, L_head = 4 R_H / 3.
  head.radius = g.head_radius;
  head.length = 4.0 * g.head_radius / 3.0;
  return std::make_shared<HelicalRobotModel>(std::move(g));
}

}  // namespace

const RobotDescriptor& helicalRobotType() {
  static const RobotDescriptor d{"helical",
                                 "rigid head, motor, plate, hook and one helical flagellum, "
                                 "untethered or on a gimbal (docs/model.md 8.4)",
                                 parseHelicalRobot};
  return d;
}

}  // namespace flagella
