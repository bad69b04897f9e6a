// Stretching energy of every edge: E_s = 1/2 EA eps^2 |ebar| (docs/model.md 1.4, 1.5).
#pragma once

#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

double stretchingEnergy(const RodNetwork& net, const VecX& q);

/// Adds dE_s/dq to gradient and, if hessian is non-null, d2E_s/dq2 to it, at the q of `frames`
/// (initialFrames or transportFrames of q): the edges' lengths and unit tangents are theirs.
void addStretchingGradientHessian(const RodNetwork& net, const ReferenceFrames& frames,
                                  VecX& gradient, SparseAssembler* hessian);

}  // namespace flagella
