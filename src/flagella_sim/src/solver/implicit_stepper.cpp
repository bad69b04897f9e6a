// ImplicitStepper's Newton solve of an implicit Euler step (docs/model.md 1.10).
#include "flagella_sim/solver/implicit_stepper.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/elastic/stretching_energy.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/solver/chord_predictor.h"

namespace flagella {

namespace {

// Routes effect Jacobian entries dF/dq into the Newton Jacobian as -dF/dq (docs/model.md 1.10).
class NegatingSink : public JacobianSink {
 public:
  explicit NegatingSink(SparseAssembler& a) : assembler_(a) {}
  void add(int row, int col, double value) override { assembler_.add(row, col, -value); }
  void addBlock(int row, int col, const Mat3& block) override {
    assembler_.subtractBlock(row, col, block);
  }

 private:
  SparseAssembler& assembler_;
};

// A stagnated Newton update is accepted only if the residual is within this factor of the
// tolerance (NewtonOptions::step_tolerance).
constexpr double kStagnationResidualFactor = 1e3;

// Damped retry (NewtonOptions::damped_retry): a step length is accepted when the scaled residual
// drops by this fraction of it (Armijo); halved at most this many times (down to about 1e-4).
constexpr double kArmijoFraction = 1e-4;
constexpr int kMaxBacktracks = 14;
// Plain Newton is stagnating when, from this iteration on, the residual is above this fraction
// per two updates of its value NewtonOptions::stagnation_updates iterations earlier while still
// far from the tolerance (not round-off).
constexpr int kStagnationCheckStart = 4;
constexpr double kStagnationRatio = 0.5;
// Chord updates (NewtonOptions::jacobian_reuse) only in the last stretch of convergence: with the
// scaled residual below this factor times the tolerance. Farther out (a motor reversal of the
// binary-switch robot) a reused Jacobian was measured to stall Newton into the damped retry.
constexpr double kChordResidualFactor = 100.0;

}  // namespace

ImplicitStepper::ImplicitStepper(RodNetwork net, std::vector<EffectPtr> effects, Medium medium,
                                 NewtonOptions options)
    : net_(std::move(net)),
      effects_(std::move(effects)),
      medium_(std::move(medium)),
      options_(options),
      assembler_(net_.ndof()) {
  if (net_.parts.motor_spring >= 0)
    motor_tau_bar0_ = net_.bend_twist_springs.at(net_.parts.motor_spring).tau_bar;
  motor_twist_ = {net_.parts.motor_spring, motor_tau_bar0_};
  attempt_viscosity_ = medium_.viscosity();
  for (bool fixed : net_.fixed_dof) any_fixed_ = any_fixed_ || fixed;
  if (options_.block_lu) lu_.setBlocks(nodeEdgeBlocks(net_));
  dense_system_.setCondensation(options_.condensed_dense_lu);
  for (const EffectPtr& e : effects_) {
    e->attach(net_);
    if (const ForceLaw* force = e->as<ForceLaw>()) {
      forces_.push_back(force);
      if (force->hasDenseJacobian()) dense_forces_.push_back(force);
    }
    if (StepHooks* hooks = e->as<StepHooks>()) step_hooks_.push_back(hooks);
    if (MappedIterates* mapped = e->as<MappedIterates>()) mapped_iterates_.push_back(mapped);
    if (const ViscosityLaw* law = e->as<ViscosityLaw>()) viscosity_laws_.push_back(law);
    if (const MotorSpeedLaw* law = e->as<MotorSpeedLaw>()) speed_laws_.push_back(law);
  }
  dense_ = !dense_forces_.empty();
}

Effect* ImplicitStepper::findEffect(const std::string& name) const {
  for (const EffectPtr& e : effects_)
    if (e->name() == name) return e.get();
  return nullptr;
}

RodState ImplicitStepper::initialState() const {
  RodState s;
  s.time = 0.0;
  s.q = net_.restDofs();
  s.qdot = VecX::Zero(net_.ndof());
  s.frames = initialFrames(net_, s.q);
  s.motor_twist_offset = 0.0;
  return s;
}

double ImplicitStepper::scaledResidual(const VecX& f) const {
  const int npos = 3 * net_.numNodes();
  const double force = f.head(npos).cwiseAbs().maxCoeff() / options_.force_scale;
  const double moment = net_.numEdges() > 0
                            ? f.tail(net_.numEdges()).cwiseAbs().maxCoeff() / options_.moment_scale
                            : 0.0;
  return std::max(force, moment);
}

void ImplicitStepper::pinFixedDofs(SparseMatrix& J) const {
  // Dirichlet DOFs: zero row and column, unit diagonal (docs/model.md 1.10).
  for (int col = 0; col < J.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(J, col); it; ++it)
      if (net_.fixed_dof[it.row()] || net_.fixed_dof[col])
        it.valueRef() = it.row() == col ? 1.0 : 0.0;
}

double ImplicitStepper::stepNorm(const VecX& dq) const {
  const int npos = 3 * net_.numNodes();
  const double positions = dq.head(npos).cwiseAbs().maxCoeff() / options_.length_scale;
  const double angles = net_.numEdges() ? dq.tail(net_.numEdges()).cwiseAbs().maxCoeff() : 0.0;
  return std::max(positions, angles);
}

double ImplicitStepper::evaluate(const RodState& start, const VecX& q, double dt,
                                 const ReferenceFrames& frames, bool with_jacobian) {
  // docs/model.md 1.10: f = (m/dt)((q - q_k)/dt - qdot_k) + dE/dq - F_ext,
  //            J = m/dt^2 + d2E/dq2 - dF_ext/dq
  if (profile_) {
    ++profile_->residuals;
    profile_->jacobians += with_jacobian;
  }
  ProfileScope whole(profile_, with_jacobian ? &StepProfile::jacobian_evaluations
                                             : &StepProfile::residual_evaluations);
  const VecX& q0 = start.q;
  const VecX& v0 = start.qdot;
  SparseAssembler* hessian = with_jacobian ? &assembler_ : nullptr;
  if (with_jacobian) {
    ProfileScope timer(profile_, &StepProfile::assembly);
    if (assembler_.redirected()) lu_.blockLu().clearStorage();
    assembler_.begin();
  }
  {
    ProfileScope timer(profile_, &StepProfile::elastic);
    residual_ = net_.lumped_mass.cwiseProduct(q - q0 - dt * v0) / (dt * dt);
    if (with_jacobian)
      for (int i = 0; i < net_.ndof(); ++i) assembler_.add(i, i, net_.lumped_mass(i) / (dt * dt));
    addStretchingGradientHessian(net_, frames, residual_, hessian);
    addBendTwistGradientHessian(net_, q, frames, residual_, hessian, motor_twist_);
  }
  const EffectContext ctx = contextAt(start, q, dt, frames);
  {
    ProfileScope timer(profile_, &StepProfile::effects);
    external_.setZero(net_.ndof());
    NegatingSink sink(assembler_);
    for (const ForceLaw* force : forces_)
      force->addForce(ctx, external_, with_jacobian ? &sink : nullptr);
    residual_ -= external_;
  }
  if (with_jacobian) {
    ProfileScope timer(profile_, &StepProfile::assembly);
    SparseMatrix& J = assembler_.finish();
    if (any_fixed_) pinFixedDofs(J);
    if (dense_ && krylov_attempt_) {
      product_.begin(J, net_.fixed_dof);
      addDenseBlocks(ctx, product_);
    } else if (dense_) {
      buildDenseJacobian(ctx);
    }
  }
  ProfileScope timer(profile_, &StepProfile::convergence);
  if (any_fixed_)
    for (int i = 0; i < residual_.size(); ++i)
      if (net_.fixed_dof[i]) residual_(i) = 0.0;
  return residual_.allFinite() ? scaledResidual(residual_)
                               : std::numeric_limits<double>::infinity();
}

EffectContext ImplicitStepper::contextAt(const RodState& start, const VecX& q, double dt,
                                         const ReferenceFrames& frames) const {
  return {net_, q, frames, start.q, start.qdot, dt, start.time + dt, medium_, attempt_viscosity_};
}

void ImplicitStepper::addDenseBlocks(const EffectContext& ctx, DenseJacobianSink& sink) const {
  for (const ForceLaw* force : dense_forces_) force->addDenseJacobian(ctx, sink);
}

void ImplicitStepper::buildDenseJacobian(const EffectContext& ctx) {
  dense_system_.begin(assembler_.matrix(), net_.fixed_dof);
  addDenseBlocks(ctx, dense_system_);
}

void ImplicitStepper::transportInto(const VecX& q, const ReferenceFrames& previous,
                                    ReferenceFrames& frames) const {
  ProfileScope timer(profile_, &StepProfile::frames);
  transportFrames(net_, q, previous, frames);
}

ImplicitStepper::Attempt ImplicitStepper::solveStep(const RodState& start, RodState& result,
                                                    double dt, double motor_offset,
                                                    double viscosity, bool damped) {
  Attempt attempt;
  beginAttempt(dt, motor_offset, viscosity, damped);
  // The iterate lives in iterate_ and its frames in frames_ (storage reused); an accepted step
  // swaps the frames in.
  VecX& q = iterate_;
  setInitialGuess(start, dt, q);
  // docs/model.md 4.4: forces followed by preimage predict their own DOFs (unless the rotating
  // predictor was asked for, which keeps them)
  if (krylov_attempt_ && !options_.rotating_predictor)
    for (MappedIterates* mapped : mapped_iterates_) mapped->predictIterate(start, dt, q);
  // Modified Newton (NewtonOptions::jacobian_reuse): the first update of every attempt uses a
  // fresh Jacobian (one from the previous step was measured to contract 5-20x worse: the stiff
  // head has turned since), later ones reuse the factored one while the residual contracts fast.
  NewtonProgress progress;
  for (int iter = 0; iter <= options_.max_iterations; ++iter) {
    bool built = false;
    const IterateVerdict verdict = testIterate(start, dt, iter, progress, attempt, built);
    if (verdict == IterateVerdict::kFailed) return attempt;
    if (verdict == IterateVerdict::kConverged) {
      acceptAttempt(start, result, dt, attempt);
      return attempt;
    }
    if (isStagnating(iter, attempt.residual, progress, damped))
      return attempt.fail("stagnation (residual not halved in two updates)");
    if (const char* failure =
            computeUpdate(start, dt, iter, attempt.residual, built, damped, progress))
      return attempt.fail(failure);
    const bool round_off = isRoundOffUpdate(update_, attempt.residual);
    // A round-off-level update needs no line search: the residual cannot descend further.
    if (damped && !round_off && !backtrackUpdate(start, dt, attempt.residual))
      return attempt.fail("no descent along the Newton direction");
    if (progress.last_update_chord) previous_iterate_ = q;
    const bool follow = krylov_attempt_ && !mapped_iterates_.empty();
    if (follow) mapped_from_ = q;
    q -= update_;
    if (follow)  // update_ = C preimage_ (docs/model.md 4.4)
      for (MappedIterates* mapped : mapped_iterates_)
        mapped->noteMappedUpdate(mapped_from_, q, preimage_, dense_system_.mappingMatrix(),
                                 dense_system_.mappingScale());
    if (round_off) {
      // Round-off-level update with a nearly converged residual: accept (NewtonOptions).
      transportInto(q, start.frames, frames_);
      acceptAttempt(start, result, dt, attempt);
      return attempt;
    }
  }
  return attempt.fail("no convergence within max_iterations");
}

void ImplicitStepper::beginAttempt(double dt, double motor_offset, double viscosity, bool damped) {
  // the residual history (NewtonProgress) holds the window; options() may change between steps
  if (options_.stagnation_updates < NewtonOptions::kMinStagnationUpdates ||
      options_.stagnation_updates > NewtonOptions::kMaxStagnationUpdates)
    throw std::invalid_argument("NewtonOptions::stagnation_updates must be in [" +
                                std::to_string(NewtonOptions::kMinStagnationUpdates) + ", " +
                                std::to_string(NewtonOptions::kMaxStagnationUpdates) + "], got " +
                                std::to_string(options_.stagnation_updates));
  motor_twist_.tau_bar = motor_tau_bar0_ + motor_offset;
  attempt_viscosity_ = viscosity;
  attempt_dt_ = dt;
  krylov_attempt_ = dense_ && options_.krylov_iterations > 0 && !damped;
}

void ImplicitStepper::setInitialGuess(const RodState& start, double dt, VecX& q) const {
  const VecX& q0 = start.q;
  if (options_.extrapolate_initial_guess)
    q = q0 + dt * start.qdot;
  else
    q = q0;
  // Second-order predictor: the velocity extrapolated linearly from the last two steps, when this
  // step continues the last accepted one with the same dt.
  const bool history = options_.extrapolate_initial_guess && predictor_.valid &&
                       predictor_.time == start.time && predictor_.dt == dt &&
                       predictor_.qdot_end.size() == start.qdot.size() &&
                       predictor_.qdot_end == start.qdot;
  if (history) q += dt * (start.qdot - predictor_.qdot_start);
  if (history && options_.rotating_predictor)
    for (int i = 0; i < net_.numNodes(); ++i) {
      const int at = RodNetwork::positionIndex(i);
      q.segment<3>(at) =
          q0.segment<3>(at) + dt * rotatingChordPrediction(predictor_.qdot_start.segment<3>(at),
                                                           start.qdot.segment<3>(at));
    }
  for (int i = 0; i < q.size(); ++i)
    if (net_.fixed_dof[i]) q(i) = q0(i);
}

ImplicitStepper::IterateVerdict ImplicitStepper::testIterate(const RodState& start, double dt,
                                                             int iter, NewtonProgress& progress,
                                                             Attempt& attempt, bool& built) {
  // The first pass always builds the Jacobian; later passes first check convergence with the
  // cheap residual-only evaluation and build the Jacobian only if another update needs a fresh
  // one.
  VecX& q = iterate_;
  transportInto(q, start.frames, frames_);
  built = iter == 0;
  attempt.residual = evaluate(start, q, dt, frames_, built);
  attempt.iterations = iter;
  if (options_.trace)
    std::fprintf(stderr, "t=%.4f iter %d residual %.3e%s\n", start.time, iter, attempt.residual,
                 progress.last_update_chord ? " (chord)" : "");
  if (progress.last_update_chord && !(attempt.residual < progress.residualOf(iter - 1))) {
    // The chord update raised the residual: undo it and rebuild the Jacobian there.
    q = previous_iterate_;
    transportInto(q, start.frames, frames_);
    attempt.residual = evaluate(start, q, dt, frames_, true);
    built = true;
  } else {
    if (!std::isfinite(attempt.residual)) {
      attempt.fail("a non-finite residual");
      return IterateVerdict::kFailed;
    }
    if (attempt.residual < options_.residual_tolerance) return IterateVerdict::kConverged;
    if (iter == options_.max_iterations) {
      attempt.fail("no convergence within max_iterations");
      return IterateVerdict::kFailed;
    }
  }
  progress.record(iter, attempt.residual);
  return IterateVerdict::kUpdate;
}

bool ImplicitStepper::isStagnating(int iter, double residual, const NewtonProgress& progress,
                                   bool damped) const {
  const int window = options_.stagnation_updates;
  return !damped && options_.damped_retry && iter >= std::max(kStagnationCheckStart, window) &&
         residual > kStagnationResidualFactor * options_.residual_tolerance &&
         residual > std::pow(kStagnationRatio, 0.5 * window) * progress.residualOf(iter - window);
}

const char* ImplicitStepper::computeUpdate(const RodState& start, double dt, int iter,
                                           double residual, bool built, bool damped,
                                           NewtonProgress& progress) {
  const VecX& q = iterate_;
  VecX& dq = update_;
  if (krylov_attempt_) {
    if (!built) evaluate(start, q, dt, frames_, true);
    if (!krylovUpdate(start, q, dt, frames_)) return "a singular Jacobian";
    progress.last_update_chord = false;
  } else {
    // (Past the first pass a factored Jacobian always exists: a failed factorization returns.)
    const bool chord = !built && !damped &&
                       residual < options_.jacobian_reuse * progress.residualOf(iter - 1) &&
                       residual < kChordResidualFactor * options_.residual_tolerance;
    if (!chord && !factorAt(start, q, dt, frames_, built)) return "a singular Jacobian";
    progress.last_update_chord = chord;
    solveJacobian(residual_, dq);
  }
  if (!dq.allFinite()) return "a non-finite update";
  return nullptr;
}

bool ImplicitStepper::isRoundOffUpdate(const VecX& dq, double residual) const {
  ProfileScope timer(profile_, &StepProfile::convergence);
  return stepNorm(dq) < options_.step_tolerance &&
         residual < kStagnationResidualFactor * options_.residual_tolerance;
}

bool ImplicitStepper::backtrackUpdate(const RodState& start, double dt, double residual) {
  const VecX& q = iterate_;
  VecX& dq = update_;
  double length = 1.0;
  for (int k = 0;; ++k) {
    const VecX trial = q - length * dq;
    transportInto(trial, start.frames, trial_frames_);
    const double r = evaluate(start, trial, dt, trial_frames_, false);
    if (r < (1.0 - kArmijoFraction * length) * residual) break;
    if (k == kMaxBacktracks) return false;
    length *= 0.5;
  }
  dq *= length;
  return true;
}

void ImplicitStepper::acceptAttempt(const RodState& start, RodState& result, double dt,
                                    Attempt& attempt) {
  const VecX& q = iterate_;
  attempt.converged = true;
  predictor_.qdot_start = start.qdot;
  result.qdot = (q - start.q) / dt;
  predictor_.qdot_end = result.qdot;
  predictor_.time = start.time + dt;
  predictor_.dt = dt;
  predictor_.valid = true;
  result.q = q;
  std::swap(result.frames, frames_);
}

}  // namespace flagella
