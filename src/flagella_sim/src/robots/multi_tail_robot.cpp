#include "flagella_sim/robots/multi_tail_robot.h"

#include <cmath>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/robots/rigid_head.h"

namespace flagella {

namespace {
double perTail(const std::vector<double>& v, int k) { return v.empty() ? 1.0 : v.at(k); }
}  // namespace

RodNetwork buildMultiTailRobot(const MultiTailGeometry& g) {
  if (g.n_tails < 1) throw ConfigError(rangeMessage("robot.n_tails", g.n_tails, 1, 64));
  if (!g.tail_length_scale.empty() && static_cast<int>(g.tail_length_scale.size()) != g.n_tails)
    throw ConfigError("robot.tail_length_scale needs one entry per tail (" +
                      std::to_string(g.n_tails) + ")");
  if (!g.tail_stiffness_scale.empty() &&
      static_cast<int>(g.tail_stiffness_scale.size()) != g.n_tails)
    throw ConfigError("robot.tail_stiffness_scale needs one entry per tail (" +
                      std::to_string(g.n_tails) + ")");

  NetworkBuilder b;
  const RodMaterial& m = g.tail_material;
  const double h = g.head_edge_length;
  // docs/model.md 8.1: x_0 = (0,0,-a), x_1 = 0, x_2 = (0,0,+a); tails extend toward +z
  const RigidHead head = addRigidHead(b, h, m, g.rigid_factor);
  const int x2 = head.x2, e0 = head.e0, e1 = head.e1;
  RobotParts& parts = b.parts();

  std::vector<int> spokes;
  for (int k = 0; k < g.n_tails; ++k) {
    const double phi = g.spoke_phase + 2.0 * M_PI * k / g.n_tails;
    const Vec3 root = Vec3(0, 0, h) + g.disc_radius * Vec3(std::cos(phi), std::sin(phi), 0.0);
    const int r = b.addNode(root);
    spokes.push_back(b.addEdge(x2, r, m, g.rigid_factor));
    b.addBendTwistSpring(e1, spokes.back(), m, g.rigid_factor);
    parts.head_nodes.push_back(r);
  }
  // docs/model.md 8.1: spoke pairs at x_2 (the first spoke of each pair is flipped,
  // docs/model.md 1.6)
  if (g.n_tails == 2) b.addBendTwistSpring(spokes[0], spokes[1], m, g.rigid_factor);
  if (g.n_tails >= 3)
    for (int k = 0; k < g.n_tails; ++k)
      b.addBendTwistSpring(spokes[k], spokes[(k + 1) % g.n_tails], m, g.rigid_factor);

  for (int k = 0; k < g.n_tails; ++k) {
    RodMaterial tail = m;
    tail.youngs_modulus *= perTail(g.tail_stiffness_scale, k);
    const double dl = g.tail_length * perTail(g.tail_length_scale, k) / g.tail_edges;
    const int root = parts.head_nodes[3 + k];
    std::vector<int> nodes{root};
    std::vector<int> edges;
    const double phi = g.spoke_phase + 2.0 * M_PI * k / g.n_tails;
    const Vec3 root_pos = Vec3(0, 0, h) + g.disc_radius * Vec3(std::cos(phi), std::sin(phi), 0.0);
    for (int j = 1; j <= g.tail_edges; ++j) {
      nodes.push_back(b.addNode(root_pos + Vec3(0, 0, j * dl)));
      edges.push_back(b.addEdge(nodes[j - 1], nodes[j], tail));
    }
    // docs/model.md 8.1 [ASSUMED]: the tail root is glued into the plate, so the root spring is
    // rigid
    b.addBendTwistSpring(spokes[k], edges.front(), m, g.rigid_factor);
    for (size_t j = 0; j + 1 < edges.size(); ++j)
      b.addBendTwistSpring(edges[j], edges[j + 1], tail);
    parts.tail_nodes.push_back(nodes);
    parts.tail_edges.push_back(edges);
  }
  return b.build(e0);
}

}  // namespace flagella
