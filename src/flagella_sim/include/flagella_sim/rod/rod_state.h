// The evolving state of a rod network at one instant (docs/model.md 1.1, 1.7).
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

/// Reference frame of each edge plus the per-spring reference twist history.
struct ReferenceFrames {
  std::vector<Vec3> tangent;            ///< t^j, unit, stored orientation
  std::vector<double> edge_length;      ///< |x_end - x_start| of edge j (the q of the tangents)
  std::vector<Vec3> d1;                 ///< reference director d1^j, perpendicular to t^j
  std::vector<Vec3> d2;                 ///< d2^j = t^j x d1^j
  std::vector<double> reference_twist;  ///< m_ref per bending-twisting spring (local rep.)
};

/// Full state carried between steps.
struct RodState {
  double time = 0.0;
  VecX q;     ///< DOFs at time
  VecX qdot;  ///< DOF rates at time
  ReferenceFrames frames;
  double motor_twist_offset = 0.0;  ///< integral of omega dt added to the motor's tau_bar(0)
};

}  // namespace flagella
