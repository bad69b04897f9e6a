// Stretching energy of every edge: E_s = 1/2 EA eps^2 |ebar| (docs/model.md 1.4, 1.5).
#pragma once

#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

double stretchingEnergy(const RodNetwork& net, const VecX& q);

/// Adds dE_s/dq to gradient and, if hessian is non-null, d2E_s/dq2 to it.
void addStretchingGradientHessian(const RodNetwork& net, const VecX& q, VecX& gradient,
                                  SparseAssembler* hessian);
/// The same with the edges' lengths and unit tangents taken from `frames` (those of q: the
/// stepper's transported frames), not recomputed from q; the same arithmetic.
void addStretchingGradientHessian(const RodNetwork& net, const ReferenceFrames& frames,
                                  VecX& gradient, SparseAssembler* hessian);

}  // namespace flagella
