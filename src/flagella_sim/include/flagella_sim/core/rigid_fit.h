// Best-fit rigid motion between two point sets (Kabsch 1976, Acta Cryst. A32: 922): the rotation
// R and translation c minimising sum |x_i - (R y_i + c)|^2, and the largest remaining distance.
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

struct RigidFit {
  Mat3 rotation = Mat3::Identity();  ///< R, a proper rotation (det +1)
  Vec3 translation = Vec3::Zero();   ///< c
  double deviation = 0.0;            ///< max_i |x_i - (R y_i + c)|
};

/// Best fit x_i ~ R y_i + c; `from` (y) and `to` (x) have the same, non-zero size.
RigidFit bestRigidFit(const std::vector<Vec3>& from, const std::vector<Vec3>& to);

}  // namespace flagella
