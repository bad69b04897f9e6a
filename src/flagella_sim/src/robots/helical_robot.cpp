#include "flagella_sim/robots/helical_robot.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/robots/rigid_head.h"

namespace flagella {

namespace {

constexpr int kMinHelixEdges = 4;
constexpr int kMaxHelixEdges = 20000;
// docs/model.md 1.8: the head nodes x_0, x_1 carry this many flagellum-node masses.
constexpr double kHeadMassInFlagellumNodes = 10.0;

void requirePositive(const std::string& field, double value, const std::string& unit) {
  if (!(value > 0.0 && std::isfinite(value)))
    throw ConfigError(field + " must be > 0" + (unit.empty() ? "" : " " + unit) + ", got " +
                      formatNumber(value));
}

// Helix nodes x_4 .. x_{N-1}: hook e^3 from the plate rim x_3, then equal-arc-length edges
// (docs/model.md 8.4.1); every spring here has the flagellum's stiffness except T2 at x_3 and
// the hook's joint at x_4 (hook_stiffness_scale times it).
void addFlagellum(NetworkBuilder& b, const HelicalGeometry& g, int plate_edge, int rim) {
  const RodMaterial& m = g.flagellum;
  std::vector<int> nodes{rim, b.addNode(g.helixPoint(0.0))};
  std::vector<int> edges{b.addEdge(rim, nodes.back(), m)};            // hook e^3
  b.addBendTwistSpring(plate_edge, edges.back(), m, g.rigid_factor);  // T2 at x_3 (rigid)
  const int n = g.helixEdges();
  const double phi_end = 2.0 * M_PI * g.pitch_count;
  for (int j = 1; j <= n; ++j) {
    nodes.push_back(b.addNode(g.helixPoint(phi_end * j / n)));
    edges.push_back(b.addEdge(nodes[nodes.size() - 2], nodes.back(), m));
    // (e3, e4) at x_4, the hook's joint (docs/model.md 8.4.1), then the helix springs
    b.addBendTwistSpring(edges[edges.size() - 2], edges.back(), m,
                         j == 1 ? g.hook_stiffness_scale : 1.0);
  }
  b.parts().tail_nodes = {nodes};
  b.parts().tail_edges = {edges};
}

// docs/model.md 1.8, 8.4.1: m_0 = m_1 = 10 m_x, m_x the lumped mass of an interior helix node.
void setHeadMasses(RodNetwork& net) {
  const std::vector<int> helix = helixNodes(net.parts);
  const double m_x = net.lumped_mass(RodNetwork::positionIndex(helix[helix.size() / 2]));
  for (int node : {net.parts.head_front_node, net.parts.head_center_node})
    net.lumped_mass.segment<3>(RodNetwork::positionIndex(node))
        .setConstant(kHeadMassInFlagellumNodes * m_x);
}

// docs/model.md 8.4.2: the gimbal pivot x_0 is fixed, and so is the housing's roll theta^0.
void fixGimbal(RodNetwork& net) {
  const int x0 = net.parts.head_front_node;
  for (int a = 0; a < 3; ++a) net.fixed_dof[RodNetwork::positionIndex(x0) + a] = true;
  net.fixed_dof[net.thetaIndex(net.parts.head_edge)] = true;
}

void validateSelfIntersection(const HelicalGeometry& g) {
  const double r0 = g.flagellum.radius;
  if (g.pitch <= 2.0 * r0)
    throw ConfigError("robot.pitch must be > 2 robot.filament_radius = " + formatNumber(2.0 * r0) +
                      " m, got " + formatNumber(g.pitch) +
                      ": adjacent turns of the helix would touch (self-intersection)");
  if (g.helix_radius <= r0)
    throw ConfigError("robot.helix_radius must be > robot.filament_radius = " + formatNumber(r0) +
                      " m, got " + formatNumber(g.helix_radius) +
                      ": the filament would cross the helix axis (self-intersection)");
}

void validateEdgeCount(const HelicalGeometry& g) {
  const double edges = g.arcLength() / g.edge_length;  // before rounding: no int overflow
  const auto message = [&](const std::string& bound, double limit) {
    return "robot.edge_length must be " + bound + " L_arc / " + formatNumber(limit) + " = " +
           formatNumber(g.arcLength() / limit) + " m (L_arc = " + formatNumber(g.arcLength()) +
           " m), got " + formatNumber(g.edge_length);
  };
  if (edges < kMinHelixEdges - 0.5)
    throw ConfigError(message("<=", kMinHelixEdges - 0.5) + ": fewer than " +
                      std::to_string(kMinHelixEdges) + " helix edges");
  if (edges > kMaxHelixEdges + 0.5)
    throw ConfigError(message(">=", kMaxHelixEdges + 0.5) + ": more than " +
                      std::to_string(kMaxHelixEdges) + " helix edges");
}

}  // namespace

double HelicalGeometry::arcLength() const {
  // docs/model.md 8.4.1: L_arc = (L_t / lambda) sqrt((2 pi R_t)^2 + lambda^2)
  return pitch_count * std::hypot(2.0 * M_PI * helix_radius, pitch);
}

int HelicalGeometry::helixEdges() const {
  return std::max(2, static_cast<int>(std::lround(arcLength() / edge_length)));
}

Vec3 HelicalGeometry::helixPoint(double phi) const {
  // docs/model.md 8.4.1: x(phi) = c + (lambda phi / 2 pi) z + R_t (cos phi x + chi sin phi y),
  // c = (0, 0, R_H + L_h), so that x(0) = x_4 lies axially above the plate rim x_3.
  return Vec3(helix_radius * std::cos(phi), handedness * helix_radius * std::sin(phi),
              head_radius + hook_length + pitch * phi / (2.0 * M_PI));
}

void validateHelicalGeometry(const HelicalGeometry& g) {
  const std::pair<const char*, double> lengths[] = {{"robot.head_radius", g.head_radius},
                                                    {"robot.helix_radius", g.helix_radius},
                                                    {"robot.pitch", g.pitch},
                                                    {"robot.filament_radius", g.flagellum.radius},
                                                    {"robot.edge_length", g.edge_length}};
  for (const auto& [field, value] : lengths) requirePositive(field, value, "m");
  requirePositive("robot.youngs_modulus", g.flagellum.youngs_modulus, "Pa");
  requirePositive("robot.density", g.flagellum.density, "kg/m^3");
  requirePositive("robot.rigid_factor", g.rigid_factor, "");
  requirePositive("robot.hook_stiffness_scale", g.hook_stiffness_scale, "");
  if (g.handedness != kRightHanded && g.handedness != kLeftHanded)
    throw ConfigError("robot.handedness must be right (+1) or left (-1), got " +
                      std::to_string(g.handedness));
  requireInRange("robot.pitch_count", g.pitch_count, kMinPitchCount, kMaxPitchCount);
  validateSelfIntersection(g);
  const double L_t = g.axialLength();
  if (!(g.hook_length > 0.0 && g.hook_length <= L_t))
    throw ConfigError("robot.hook_length must be in (0, L_t] = (0, " + formatNumber(L_t) +
                      "] m, got " + formatNumber(g.hook_length) +
                      (g.hook_length > L_t ? ": hook longer than the helix's axial length" : ""));
  validateEdgeCount(g);
}

RodNetwork buildHelicalRobot(const HelicalGeometry& g) {
  validateHelicalGeometry(g);
  NetworkBuilder b;
  const RodMaterial& m = g.flagellum;
  const double k = g.rigid_factor;
  // docs/model.md 8.4.1: head axis +z, x_0 = (0,0,-R_H), x_1 = 0 (head centre), x_2 = (0,0,R_H);
  // the plate e^2 = x_2 -> x_3 is radial along +x, of length R_t.
  const RigidHead head = addRigidHead(b, g.head_radius, m, k);  // T0 at x_1: the motor (1.9)
  const int x3 = b.addNode(Vec3(g.helix_radius, 0, g.head_radius));
  // Rigid stretching of e^0, e^1 and the plate e^2 (docs/model.md 8.4.1 [ASSUMED] for e^2).
  const int e2 = b.addEdge(head.x2, x3, m, k);
  b.addBendTwistSpring(head.e1, e2, m, k);  // T1 at x_2
  addFlagellum(b, g, e2, x3);
  RodNetwork net = b.build(head.e0);
  setHeadMasses(net);
  if (g.mount == HelicalMount::kGimbal) fixGimbal(net);
  return net;
}

std::vector<int> helixNodes(const RobotParts& parts) {
  const std::vector<int>& chain = parts.tail_nodes.at(0);  // {x_3 (plate rim), x_4, ...}
  return std::vector<int>(chain.begin() + 1, chain.end());
}

}  // namespace flagella
