#include "support/single_tail_robot.h"

#include <string>

#include "flagella_sim/robots/multi_tail_robot.h"
#include "support/test_robots.h"

namespace flagella::testing {

namespace {

class SingleTailRobotModel : public RobotModelOf<SingleTailGeometry> {
 public:
  using RobotModelOf::RobotModelOf;
  const std::string& type() const override { return singleTailRobotType().name; }
  // Built as a multi-tail robot with one tail: a new type may reuse any builder.
  RodNetwork build() const override {
    MultiTailGeometry g;
    g.n_tails = 1;
    g.tail_length = geometry.tail_length;
    g.tail_edges = geometry.tail_edges;
    g.tail_material = geometry.material;
    g.head_edge_length = geometry.head_radius;
    g.disc_radius = geometry.head_radius;
    return buildMultiTailRobot(g);
  }
  const RodMaterial& filament() const override { return geometry.material; }
  double filamentLength() const override { return geometry.tail_length; }
  int tailCount() const override { return 1; }
  std::string label() const override { return "single tail"; }
  std::vector<SummaryField> summaryFields() const override {
    return {{"robot", type()}, {"tail_length_m", geometry.tail_length}};
  }
  std::shared_ptr<RobotModel> clone() const override {
    return std::make_shared<SingleTailRobotModel>(*this);
  }
};

std::shared_ptr<RobotModel> parseSingleTail(FieldReader& r, RobotHeadSize& head) {
  SingleTailGeometry g;
  g.material = vpsMaterial();
  g.tail_length = r.number("tail_length", g.tail_length, 1e-3, 1.0, "m");
  g.tail_edges = r.integer("tail_edges", g.tail_edges, 2, 200);
  g.head_radius = r.number("head_radius", g.head_radius, 1e-3, 0.1, "m");
  g.material.youngs_modulus =
      r.number("youngs_modulus", g.material.youngs_modulus, 1.0, 1e12, "Pa");
  head.radius = g.head_radius;
  head.length = 2.0 * g.head_radius;
  return std::make_shared<SingleTailRobotModel>(g);
}

}  // namespace

const RobotDescriptor& singleTailRobotType() {
  static const RobotDescriptor d{"test_single_tail", "a head with one straight tail (tests only)",
                                 parseSingleTail};
  return d;
}

void registerSingleTailRobot() {
  if (!findRobotDescriptor(singleTailRobotType().name)) registerRobotType(singleTailRobotType());
}

}  // namespace flagella::testing
