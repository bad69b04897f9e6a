#include "support/test_robots.h"

#include "flagella_sim/robots/multi_tail_robot.h"

namespace flagella::testing {

RodMaterial vpsMaterial() {
  RodMaterial m;
  m.youngs_modulus = 1.2e6;
  m.poisson_ratio = 0.5;
  m.radius = 3.2e-3;
  m.density = 1000.0;
  return m;
}

RodNetwork makeStraightRod(int edges, double length, const RodMaterial& material) {
  NetworkBuilder b;
  const double dl = length / edges;
  for (int i = 0; i <= edges; ++i) b.addNode(Vec3(0.0, 0.0, i * dl));
  for (int j = 0; j < edges; ++j) b.addEdge(j, j + 1, material);
  for (int j = 0; j + 1 < edges; ++j) b.addBendTwistSpring(j, j + 1, material);
  return b.build();
}

RodNetwork makeThreeTailRobot(int tail_edges) {
  MultiTailGeometry g;
  g.n_tails = 3;
  g.tail_length = 0.05;
  g.tail_edges = tail_edges;
  g.tail_material = vpsMaterial();
  return buildMultiTailRobot(g);
}

RodNetwork makeLoneHead(double half_length, const RodMaterial& material) {
  constexpr double kRigid = 1e3;  // stiffness factor: the head does not deform
  NetworkBuilder b;
  const int x0 = b.addNode(Vec3(0.0, 0.0, -half_length));
  const int x1 = b.addNode(Vec3(0.0, 0.0, 0.0));
  const int x2 = b.addNode(Vec3(0.0, 0.0, half_length));
  const int e0 = b.addEdge(x0, x1, material, kRigid);
  const int e1 = b.addEdge(x1, x2, material, kRigid);
  b.addBendTwistSpring(e0, e1, material, kRigid);
  b.parts().head_front_node = x0;
  b.parts().head_center_node = x1;
  b.parts().joint_node = x2;
  b.parts().head_edge = e0;
  b.parts().shaft_edge = e1;
  b.parts().motor_spring = -1;
  return b.build(e0);
}

RodNetwork makeJunctionNetwork(const RodMaterial& material) {
  NetworkBuilder b;
  const int c = b.addNode(Vec3(0.0, 0.0, 0.0));
  const int a1 = b.addNode(Vec3(0.0, 0.0, -0.01));
  const int a0 = b.addNode(Vec3(0.002, 0.001, -0.02));
  const int s1 = b.addNode(Vec3(0.01, 0.0, 0.001));
  const int s2 = b.addNode(Vec3(-0.005, 0.0087, 0.002));
  const int s3 = b.addNode(Vec3(-0.005, -0.0087, -0.001));
  const int t1 = b.addNode(Vec3(0.012, 0.003, 0.011));
  const int t2 = b.addNode(Vec3(-0.004, 0.0095, 0.012));
  const int e0 = b.addEdge(a0, a1, material);  // into the chain
  const int e1 = b.addEdge(a1, c, material);   // into the junction
  const int k1 = b.addEdge(c, s1, material);   // spokes leave the junction
  const int k2 = b.addEdge(c, s2, material);
  const int k3 = b.addEdge(s3, c, material);   // stored pointing into the junction
  const int f1 = b.addEdge(t1, s1, material);  // tail edge stored backwards
  const int f2 = b.addEdge(s2, t2, material);
  b.addBendTwistSpring(e0, e1, material);
  b.addBendTwistSpring(e1, k1, material);
  b.addBendTwistSpring(e1, k2, material);
  b.addBendTwistSpring(k1, k2, material);  // both leave c: E flipped
  b.addBendTwistSpring(k2, k3, material);  // E flipped, F flipped
  b.addBendTwistSpring(k3, k1, material);  // neither flipped
  b.addBendTwistSpring(k1, f1, material);  // F flipped
  b.addBendTwistSpring(k2, f2, material);
  return b.build();
}

VecX perturbed(const RodNetwork& net, const VecX& q, double amplitude, double angle,
               std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX out = q;
  for (int i = 0; i < 3 * net.numNodes(); ++i) out(i) += amplitude * u(rng);
  for (int j = 0; j < net.numEdges(); ++j) out(net.thetaIndex(j)) += angle * u(rng);
  return out;
}

}  // namespace flagella::testing
