// The multi-tail robots of docs/model.md 8.1-8.3: rigid head (x_0, x_1), motor at x_1, shaft to the
// disc centre x_2, n radial spokes, n straight tails parallel to the axis (+z).
#pragma once

#include <vector>

#include "flagella_sim/rod/network_builder.h"

namespace flagella {

struct MultiTailGeometry {
  int n_tails = 2;
  double tail_length = 0.111;      ///< L [m]
  int tail_edges = 27;             ///< edges per tail
  double head_edge_length = 0.02;  ///< |x_0 x_1| = |x_1 x_2| [m]
  double disc_radius = 0.02;       ///< R_d: spoke length [m]
  double spoke_phase = 0.0;        ///< angle of spoke 0 about the axis, from +x [rad]
  double rigid_factor = 1e3;       ///< stiffness multiplier of the rigid parts (docs/model.md 1.4)
  RodMaterial tail_material;
  /// Optional per-tail multipliers (fabrication asymmetry); empty means all 1.
  std::vector<double> tail_length_scale;
  std::vector<double> tail_stiffness_scale;
};

/// Builds the network of docs/model.md 8.1 (discretisation shared by 8.1-8.3).
RodNetwork buildMultiTailRobot(const MultiTailGeometry& geometry);

}  // namespace flagella
