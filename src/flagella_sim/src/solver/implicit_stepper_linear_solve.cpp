// ImplicitStepper's linear solve of the Newton system: block LU, KLU or dense (docs/model.md 1.10).
#include "flagella_sim/solver/implicit_stepper.h"

namespace flagella {

namespace {

// A dense Jacobian whose reciprocal condition estimate is below this is treated as singular.
constexpr double kMinDenseReciprocalCondition = 1e-15;

}  // namespace

ImplicitStepper::Factorization ImplicitStepper::factorizeJacobian(bool klu_only) {
  ProfileScope timer(profile_, &StepProfile::factorization);
  if (profile_) ++profile_->factorizations;
  ++factorizations_;
  if (dense_) {
    kept_.valid = dense_system_.factorize(kMinDenseReciprocalCondition);
    kept_.stale = false;
    kept_.dt = attempt_dt_;
    kept_.viscosity = attempt_viscosity_;
    return kept_.valid ? Factorization::kFactored : Factorization::kSingular;
  }
  if (assembler_.redirected()) {
    if (lu_.factorizeInPlace()) return Factorization::kFactored;
    assembler_.stopRedirect();
    in_place_allowed_ = false;
    return Factorization::kNeedsMatrix;
  }
  if (!analyzed_ || assembler_.patternChanged()) {
    lu_.analyze(assembler_.matrix());
    analyzed_ = true;
    ++analyses_;
  }
  if (!lu_.factorize(assembler_.matrix(), !klu_only)) return Factorization::kSingular;
  if (lu_.lastWasBlock() && in_place_allowed_ && !any_fixed_) {
    BlockSparseLu& block = lu_.blockLu();
    assembler_.redirect(block.storage(), block.storageSize(), block.valueOffsets());
  }
  return Factorization::kFactored;
}

void ImplicitStepper::solveJacobian(const VecX& rhs, VecX& dq) {
  ProfileScope timer(profile_, &StepProfile::solve);
  if (profile_) ++profile_->updates;
  if (dense_) {  // dq = C z, z kept for the forces that follow iterates (docs/model.md 4.4)
    dense_system_.solveUnmapped(rhs, preimage_);
    dense_system_.map(preimage_, dq);
  } else
    lu_.solve(rhs, dq);
}

bool ImplicitStepper::factorAt(const RodState& start, const VecX& q, double dt,
                               const ReferenceFrames& frames, bool built) {
  if (!built) evaluate(start, q, dt, frames, true);
  Factorization factored = factorizeJacobian();
  if (factored == Factorization::kNeedsMatrix) {
    // The block LU refused a Jacobian assembled in its storage: assemble it as a matrix
    // (assembly in place is off now) for KLU.
    evaluate(start, q, dt, frames, true);
    factored = factorizeJacobian(/*klu_only=*/true);
  }
  return factored == Factorization::kFactored;
}

}  // namespace flagella
