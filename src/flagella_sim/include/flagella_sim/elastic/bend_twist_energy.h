// Bending and twisting energy of the bending-twisting springs (docs/model.md 1.4, 1.5, 1.6).
#pragma once

#include <Eigen/Core>

#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/rod/rod_kinematics.h"

namespace flagella {

/// Local DOF order of one spring: [x_p(3), x_c(3), x_q(3), theta_E_loc, theta_F_loc].
using SpringVector = Eigen::Matrix<double, 11, 1>;
using SpringMatrix = Eigen::Matrix<double, 11, 11>;

/// Energy, gradient and Hessian of one spring in its local representation.
struct SpringEnergyTerms {
  double energy = 0.0;
  SpringVector gradient = SpringVector::Zero();
  SpringMatrix hessian;  ///< set only when asked for (bendTwistTerms with_hessian)
};

/// Evaluates E_b + E_t of one spring at its local geometry (docs/model.md 1.4, 1.5).
SpringEnergyTerms bendTwistTerms(const SpringGeometry& g, const BendTwistSpring& spring,
                                 bool with_hessian);

/// A spring whose natural twist is not the network's: the motor spring, driven by the motor
/// (docs/model.md 1.9). spring < 0: none.
struct NaturalTwistOverride {
  int spring = -1;
  double tau_bar = 0.0;
};

/// The network's spring `twist.spring` driven to `twist.tau_bar`: that natural twist, and the
/// shaft's frame turned back by the twist gained since t = 0 (BendTwistSpring::frame_turn).
BendTwistSpring drivenSpring(const RodNetwork& net, const NaturalTwistOverride& twist);

double bendTwistEnergy(const RodNetwork& net, const VecX& q, const ReferenceFrames& frames,
                       const NaturalTwistOverride& twist = {});

/// Adds the gradient (and Hessian if non-null) of all bending-twisting springs, mapping the
/// local representation back to global DOFs with the orientation signs (docs/model.md 1.6).
void addBendTwistGradientHessian(const RodNetwork& net, const VecX& q,
                                 const ReferenceFrames& frames, VecX& gradient,
                                 SparseAssembler* hessian, const NaturalTwistOverride& twist = {});

/// Global DOF index of each local spring DOF and the sign mapping local to global.
struct SpringDofMap {
  int index[11];
  double sign[11];
};
SpringDofMap springDofMap(const RodNetwork& net, const BendTwistSpring& spring);

}  // namespace flagella
