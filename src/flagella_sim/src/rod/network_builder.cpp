#include "flagella_sim/rod/network_builder.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_sim/rod/rod_kinematics.h"

namespace flagella {

double RodMaterial::area() const { return M_PI * radius * radius; }
double RodMaterial::shearModulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
double RodMaterial::EA() const { return youngs_modulus * area(); }
double RodMaterial::EI() const { return youngs_modulus * M_PI * std::pow(radius, 4) / 4.0; }
double RodMaterial::GJ() const { return shearModulus() * M_PI * std::pow(radius, 4) / 2.0; }

int NetworkBuilder::addNode(const Vec3& position) {
  positions_.push_back(position);
  return static_cast<int>(positions_.size()) - 1;
}

int NetworkBuilder::addEdge(int start_node, int end_node, const RodMaterial& material,
                            double stiffness_factor) {
  if (start_node < 0 || end_node < 0 || start_node >= numNodes() || end_node >= numNodes() ||
      start_node == end_node)
    throw std::invalid_argument("edge has invalid nodes " + std::to_string(start_node) + " -> " +
                                std::to_string(end_node));
  edges_.push_back({start_node, end_node});
  edge_materials_.push_back(material);
  edge_stiffness_factor_.push_back(stiffness_factor);
  return static_cast<int>(edges_.size()) - 1;
}

int NetworkBuilder::addBendTwistSpring(int edge_e, int edge_f, const RodMaterial& material,
                                       double stiffness_factor) {
  const EdgeDef& E = edges_.at(edge_e);
  const EdgeDef& F = edges_.at(edge_f);
  int shared = -1;
  for (int a : {E.start_node, E.end_node})
    for (int b : {F.start_node, F.end_node})
      if (a == b) shared = a;
  if (shared < 0)
    throw std::invalid_argument("bending-twisting spring on edges " + std::to_string(edge_e) +
                                " and " + std::to_string(edge_f) + " that share no node");
  BendTwistSpring s;
  s.edge_e = edge_e;
  s.edge_f = edge_f;
  s.node_c = shared;
  // docs/model.md 1.6: s_g = +1 if the stored direction is the required local one (E into c, F out
  // of c)
  s.sign_e = E.end_node == shared ? 1 : -1;
  s.sign_f = F.start_node == shared ? 1 : -1;
  s.node_p = E.end_node == shared ? E.start_node : E.end_node;
  s.node_q = F.start_node == shared ? F.end_node : F.start_node;
  s.EI = stiffness_factor * material.EI();
  s.GJ = stiffness_factor * material.GJ();
  springs_.push_back(s);
  return static_cast<int>(springs_.size()) - 1;
}

void NetworkBuilder::setNodeMass(int node, double mass) {
  mass_overrides_.emplace_back(node, mass);
}

RodNetwork NetworkBuilder::build(int root_edge) const {
  RodNetwork net;
  net.rest_positions = positions_;
  net.edges = edges_;
  net.parts = parts_;
  const int ne = static_cast<int>(edges_.size());
  if (ne != numNodes() - 1)
    throw std::invalid_argument("rod network must be a tree: " + std::to_string(numNodes()) +
                                " nodes need " + std::to_string(numNodes() - 1) + " edges, got " +
                                std::to_string(ne));
  for (int j = 0; j < ne; ++j) {
    const double len = (positions_[edges_[j].end_node] - positions_[edges_[j].start_node]).norm();
    net.rest_lengths.push_back(len);
    net.edge_radius.push_back(edge_materials_[j].radius);
    net.stretch_springs.push_back({j, edge_stiffness_factor_[j] * edge_materials_[j].EA(), len});
  }
  net.bend_twist_springs = springs_;
  for (BendTwistSpring& s : net.bend_twist_springs)  // docs/model.md 1.4: undeformed Voronoi length
    s.voronoi_length = 0.5 * (net.rest_lengths[s.edge_e] + net.rest_lengths[s.edge_f]);

  // docs/model.md 1.8: m_i = rho A l_i (Voronoi), I_j = 1/2 rho A |ebar| r0^2
  net.lumped_mass = VecX::Zero(net.ndof());
  for (int j = 0; j < ne; ++j) {
    const RodMaterial& m = edge_materials_[j];
    const double edge_mass = m.density * m.area() * net.rest_lengths[j];
    for (int node : {edges_[j].start_node, edges_[j].end_node})
      net.lumped_mass.segment<3>(3 * node).array() += 0.5 * edge_mass;
    net.lumped_mass(net.thetaIndex(j)) = 0.5 * edge_mass * m.radius * m.radius;
  }
  for (const auto& [node, mass] : mass_overrides_)
    net.lumped_mass.segment<3>(3 * node).setConstant(mass);
  net.fixed_dof.assign(net.ndof(), false);

  // Natural strains from the undeformed configuration at t = 0 (docs/model.md 1.4).
  const VecX q0 = net.restDofs();
  const ReferenceFrames frames = initialFrames(net, q0, root_edge);
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    BendTwistSpring& s = net.bend_twist_springs[i];
    const SpringGeometry g = springGeometry(net, s, q0, frames, static_cast<int>(i));
    if (1.0 + g.te.dot(g.tf) < 1e-6)
      throw std::invalid_argument("bending-twisting spring " + std::to_string(i) +
                                  " folds back on itself (turning angle 180 deg)");
    s.kappa_bar1 = g.kappa1;
    s.kappa_bar2 = g.kappa2;
    s.tau_bar = g.tau;
  }
  return net;
}

}  // namespace flagella
