// The rigid head shared by the robots of docs/model.md 8.1-8.4: x_0 = (0,0,-h), x_1 = 0 (head
// centre), x_2 = (0,0,+h) on the +z axis, stiff edges e^0 = x_0 -> x_1 and e^1 = x_1 -> x_2 and
// the motor (a stiff bending-twisting spring) at x_1 (docs/model.md 1.9).
#pragma once

#include "flagella_sim/rod/network_builder.h"

namespace flagella {

struct RigidHead {
  int x0 = 0, x1 = 1, x2 = 2;  ///< nodes
  int e0 = 0, e1 = 1;          ///< edges
};

/// Adds the head to an empty builder and names its parts (head nodes, edges, motor spring).
RigidHead addRigidHead(NetworkBuilder& b, double half_length, const RodMaterial& material,
                       double rigid_factor);

}  // namespace flagella
