// Builds a RodNetwork from nodes, edges and springs: computes rest lengths, orientation signs,
// Voronoi lengths, natural strains at t = 0 and lumped masses (docs/model.md 1.2-1.8).
#pragma once

#include <vector>

#include "flagella_sim/rod/rod_network.h"

namespace flagella {

/// Cross-section and material of a rod segment (docs/model.md 1.4).
struct RodMaterial {
  double youngs_modulus = 0.0;  ///< E [Pa]
  double poisson_ratio = 0.5;   ///< nu
  double radius = 0.0;          ///< r0 [m]
  double density = 0.0;         ///< rho [kg/m^3], for lumped masses

  double area() const;
  double shearModulus() const;  ///< G = E / (2 (1 + nu))
  double EA() const;            ///< E pi r0^2
  double EI() const;            ///< E pi r0^4 / 4
  double GJ() const;            ///< G pi r0^4 / 2 [CORR-1]
};

class NetworkBuilder {
 public:
  int addNode(const Vec3& position);
  /// Adds an edge start -> end with a stretching spring of EA scaled by stiffness_factor.
  int addEdge(int start_node, int end_node, const RodMaterial& material,
              double stiffness_factor = 1.0);
  /// Adds a bending-twisting spring on two edges that share a node; the orientation signs
  /// of docs/model.md 1.6 are worked out from the stored edge directions.
  int addBendTwistSpring(int edge_e, int edge_f, const RodMaterial& material,
                         double stiffness_factor = 1.0);
  /// Overrides the lumped mass of one node (e.g. a heavier head, docs/model.md 1.8).
  void setNodeMass(int node, double mass);

  RobotParts& parts() { return parts_; }
  int numNodes() const { return static_cast<int>(positions_.size()); }

  /// Finalises the network: rest lengths, natural strains, masses (docs/model.md 1.4, 1.8).
  RodNetwork build(int root_edge = 0) const;

 private:
  std::vector<Vec3> positions_;
  std::vector<EdgeDef> edges_;
  std::vector<RodMaterial> edge_materials_;
  std::vector<double> edge_stiffness_factor_;
  std::vector<BendTwistSpring> springs_;
  std::vector<std::pair<int, double>> mass_overrides_;
  RobotParts parts_;
};

}  // namespace flagella
