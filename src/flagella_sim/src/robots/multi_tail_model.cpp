// The multi-tail robot type (docs/model.md 8.1-8.3): its config section and what the rest of
// the product asks of it (robot_model.h).
#include <cmath>

#include "flagella_sim/core/config_error.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/robots/multi_tail_robot.h"
#include "flagella_sim/robots/robot_registry.h"

namespace flagella {

namespace {

class MultiTailRobotModel : public RobotModelOf<MultiTailGeometry> {
 public:
  using RobotModelOf::RobotModelOf;
  const std::string& type() const override {
    static const std::string name = "multi_tail";
    return name;
  }
  RodNetwork build() const override { return buildMultiTailRobot(geometry); }
  const RodMaterial& filament() const override { return geometry.tail_material; }
  double filamentLength() const override { return geometry.tail_length; }
  int tailCount() const override { return geometry.n_tails; }
  std::string label() const override { return "n = " + std::to_string(geometry.n_tails); }
  std::vector<SummaryField> summaryFields() const override {
    return {{"n_tails", geometry.n_tails}, {"tail_length_m", geometry.tail_length}};
  }
  std::shared_ptr<RobotModel> clone() const override {
    return std::make_shared<MultiTailRobotModel>(*this);
  }
};

void readTailEdges(FieldReader& r, MultiTailGeometry& g) {
  const bool has_edges = r.has("tail_edges");
  const bool has_dl = r.has("tail_edge_length");
  if (has_edges && has_dl)
    throw ConfigError(r.field("tail_edges") + " and " + r.field("tail_edge_length") +
                      " are exclusive: give one");
  g.tail_edges = r.integer("tail_edges", 27, 2, 2000);
  if (has_dl) {
    const double dl = r.number("tail_edge_length", 4.11e-3, 1e-5, 1.0, "m");
    g.tail_edges = std::max(2, static_cast<int>(std::lround(g.tail_length / dl)));
  } else {
    r.describe("tail_edge_length", "", "[1e-05, 1], instead of tail_edges", "m");
  }
}

std::shared_ptr<RobotModel> parseMultiTailRobot(FieldReader& r, RobotHeadSize& head) {
  MultiTailGeometry g;
  g.n_tails = r.integer("n_tails", 2, 1, 12);
  g.tail_length = r.number("tail_length", 0.111, 1e-3, 10.0, "m");
  readTailEdges(r, g);
  g.tail_material.radius = r.number("tail_radius", 3.2e-3, 1e-5, 0.1, "m");
  g.tail_material.youngs_modulus = r.number("youngs_modulus", 1.2e6, 1.0, 1e12, "Pa");
  g.tail_material.poisson_ratio = r.number("poisson_ratio", 0.5, 0.0, 0.5);
  g.tail_material.density = r.number("density", 1000.0, 1.0, 1e5, "kg/m^3");
  head.radius = r.number("head_radius", 0.02, 1e-4, 1.0, "m");
  head.length = r.number("head_length", 2.0 * head.radius, 1e-4, 2.0, "m");
  g.head_edge_length = r.number("head_edge_length", head.radius, 1e-4, 1.0, "m");
  g.disc_radius = r.number("disc_radius", 0.02, 1e-4, 1.0, "m");
  g.spoke_phase = units::degToRad(r.number("spoke_phase_deg", 0.0, -360.0, 360.0, "deg"));
  g.rigid_factor = r.number("rigid_factor", 1e3, 1.0, 1e6);
  g.tail_length_scale = r.numberList("tail_length_scale", 0.1, 10.0);
  g.tail_stiffness_scale = r.numberList("tail_stiffness_scale", 1e-3, 1e3);
  for (const auto* list : {&g.tail_length_scale, &g.tail_stiffness_scale})
    if (!list->empty() && static_cast<int>(list->size()) != g.n_tails)
      throw ConfigError(
          r.field(list == &g.tail_length_scale ? "tail_length_scale" : "tail_stiffness_scale") +
          " needs one entry per tail (n_tails = " + std::to_string(g.n_tails) + ")");
  if (g.tail_length / g.tail_edges < 1e-5)
    throw ConfigError(r.field("tail_edges") + " gives edges shorter than 10 um");
  return std::make_shared<MultiTailRobotModel>(std::move(g));
}

}  // namespace

const RobotDescriptor& multiTailRobotType() {
  static const RobotDescriptor d{
      "multi_tail",
      "rigid head, motor, disc with n radial spokes and n straight tails (docs/model.md 8.1-8.3)",
      parseMultiTailRobot};
  return d;
}

}  // namespace flagella
