// Newton-Krylov updates of ImplicitStepper for dense Newton systems (docs/model.md 1.10, 4.4;
// NewtonOptions::krylov_iterations): GMRES on the Jacobian at the iterate, preconditioned by the
// factored Jacobian kept across steps, refactored when GMRES falls short.
#include <algorithm>
#include <cstdio>

#include "flagella_sim/solver/implicit_stepper.h"

namespace flagella {

namespace {

// A GMRES solve (NewtonOptions::krylov_iterations) stops at 0.1 x the tolerance or at this
// fraction of its right-hand side, whichever is larger (an inexact Newton forcing term, Dembo,
// Eisenstat & Steihaug 1982): the nonlinear residual a fresh Newton update leaves on the helical
// robot is 5e-4 of the last one at 150 rpm, so a linear residual below it buys nothing.
constexpr double kKrylovForcing = 1e-4;

}  // namespace

bool ImplicitStepper::refactorDense(const RodState& start, const VecX& q, double dt,
                                    const ReferenceFrames& frames) {
  {
    ProfileScope timer(profile_, &StepProfile::assembly);
    buildDenseJacobian(contextAt(start, q, dt, frames));
  }
  return factorizeJacobian() == Factorization::kFactored;
}

bool ImplicitStepper::krylovUpdate(const RodState& start, const VecX& q, double dt,
                                   const ReferenceFrames& frames) {
  const bool usable =
      kept_.valid && !kept_.stale && kept_.dt == dt && kept_.viscosity == attempt_viscosity_;
  if (usable) {
    ProfileScope timer(profile_, &StepProfile::solve);
    // GMRES on D J dq = D r, D the convergence test's row scales (docs/model.md 1.10), so that
    // its 2-norm bounds the scaled residual the update leaves: 0.1 x the tolerance.
    const int n = net_.ndof(), npos = 3 * net_.numNodes();
    row_scales_.resize(n);
    row_scales_.head(npos).setConstant(1.0 / options_.force_scale);
    row_scales_.tail(n - npos).setConstant(1.0 / options_.moment_scale);
    scaled_rhs_ = row_scales_.cwiseProduct(residual_);
    const double target =
        std::max(0.1 * options_.residual_tolerance, kKrylovForcing * scaled_rhs_.norm());
    // The preconditioner maps by the RSS matrix of this step (DenseNewtonSystem::map): the
    // product of GMRES's next vector, the one just preconditioned, then takes the RSS block from
    // its preimage without a solve (docs/model.md 4.4).
    const FactoredMatrix* mapped = dense_system_.mappingMatrix();
    const VecX* last_mapped = nullptr;
    const auto apply = [&](const VecX& v, VecX& out) {
      if (mapped && &v == last_mapped)
        product_.applyMapped(v, preimage_, mapped, dense_system_.mappingScale(), out);
      else
        product_.apply(v, out);
      out.array() *= row_scales_.array();
    };
    const auto precondition = [&](const VecX& v, VecX& out) {
      unscaled_ = v.cwiseQuotient(row_scales_);
      dense_system_.solveUnmapped(unscaled_, preimage_);
      dense_system_.map(preimage_, out);
      last_mapped = &out;
    };
    preimage_.setZero(n);  // the preimage of GMRES's x = 0 when it takes no product
    const GmresResult g =
        gmres_.solve(apply, precondition, scaled_rhs_, target, options_.krylov_iterations, update_);
    if (profile_) {
      ++profile_->updates;
      profile_->krylov_iterations += g.iterations;
    }
    if (options_.trace)
      std::fprintf(stderr, "  GMRES %d products, |r| %.3e -> %.3e (target %.3e)%s\n", g.iterations,
                   scaled_rhs_.norm(), g.residual_norm, target, g.converged ? "" : ", refactoring");
    if (g.converged) {
      kept_.stale = 2 * g.iterations >= options_.krylov_iterations;
      return true;
    }
  }
  // No usable factorisation, or GMRES fell short: factor the Jacobian at q, whose solve is then
  // the exact Newton update.
  if (!refactorDense(start, q, dt, frames)) return false;
  solveJacobian(residual_, update_);
  return true;
}

}  // namespace flagella
