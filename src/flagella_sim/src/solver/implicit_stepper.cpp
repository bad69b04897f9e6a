#include "flagella_sim/solver/implicit_stepper.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/elastic/stretching_energy.h"
#include "flagella_sim/rod/rod_kinematics.h"

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

// A dense Jacobian whose reciprocal condition estimate is below this is treated as singular.
constexpr double kMinDenseReciprocalCondition = 1e-15;

// A stagnated Newton update is accepted only if the residual is within this factor of the
// tolerance (NewtonOptions::step_tolerance).
constexpr double kStagnationResidualFactor = 1e3;

// Damped retry (NewtonOptions::damped_retry): a step length is accepted when the scaled residual
// drops by this fraction of it (Armijo); halved at most this many times (down to about 1e-4).
constexpr double kArmijoFraction = 1e-4;
constexpr int kMaxBacktracks = 14;
// Plain Newton is stagnating when, from this iteration on, the residual is above this fraction
// of its value two iterations earlier while still far from the tolerance (not round-off).
constexpr int kStagnationCheckStart = 4;
constexpr double kStagnationRatio = 0.5;
// Chord updates (NewtonOptions::jacobian_reuse) only in the last stretch of convergence: with the
// scaled residual below this factor times the tolerance. Farther out (a motor reversal of the
// binary-switch robot) a reused Jacobian was measured to stall Newton into the damped retry.
constexpr double kChordResidualFactor = 100.0;
// A failed step names a joint folded beyond this turning angle (cos = -0.999, about 177.4 deg).
const double kFoldedJointAngle = std::acos(-0.999);

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
  for (const EffectPtr& e : effects_) {
    e->attach(net_);
    dense_ = dense_ || e->hasDenseJacobian();
  }
}

std::vector<const Effect*> ImplicitStepper::motorSpeedLaws() const {
  std::vector<const Effect*> laws;
  for (const EffectPtr& e : effects_)
    if (e->shapesMotorSpeed()) laws.push_back(e.get());
  return laws;
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
    for (const EffectPtr& e : effects_)
      e->addForce(ctx, external_, with_jacobian ? &sink : nullptr);
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
  for (const EffectPtr& e : effects_)
    if (e->hasDenseJacobian()) e->addDenseJacobian(ctx, sink);
}

void ImplicitStepper::buildDenseJacobian(const EffectContext& ctx) {
  dense_system_.begin(assembler_.matrix(), net_.fixed_dof);
  addDenseBlocks(ctx, dense_system_);
}

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
  if (dense_)
    dq = dense_system_.solve(rhs);
  else
    lu_.solve(rhs, dq);
}

void ImplicitStepper::transportInto(const VecX& q, const ReferenceFrames& previous,
                                    ReferenceFrames& frames) const {
  ProfileScope timer(profile_, &StepProfile::frames);
  transportFrames(net_, q, previous, frames);
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

ImplicitStepper::Attempt ImplicitStepper::solveStep(const RodState& start, RodState& result,
                                                    double dt, double motor_offset,
                                                    double viscosity, bool damped) {
  Attempt attempt;
  motor_twist_.tau_bar = motor_tau_bar0_ + motor_offset;
  attempt_viscosity_ = viscosity;
  attempt_dt_ = dt;
  krylov_attempt_ = dense_ && options_.krylov_iterations > 0 && !damped;
  const VecX& q0 = start.q;
  VecX& q = iterate_;
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
  for (int i = 0; i < q.size(); ++i)
    if (net_.fixed_dof[i]) q(i) = q0(i);
  // The iterate's frames live in frames_ (storage reused); an accepted step swaps them in.
  ReferenceFrames& frames = frames_;
  auto failed = [&](const char* reason) {
    attempt.failure = reason;
    return attempt;
  };
  auto accept = [&]() {
    attempt.converged = true;
    predictor_.qdot_start = start.qdot;
    result.qdot = (q - q0) / dt;
    predictor_.qdot_end = result.qdot;
    predictor_.time = start.time + dt;
    predictor_.dt = dt;
    predictor_.valid = true;
    result.q = q;
    std::swap(result.frames, frames_);
  };
  // Modified Newton (NewtonOptions::jacobian_reuse): the first update of every attempt uses a
  // fresh Jacobian (one from the previous step was measured to contract 5-20x worse: the stiff
  // head has turned since), later ones reuse the factored one while the residual contracts fast.
  bool last_update_chord = false;
  double residual_history[3] = {0.0, 0.0, 0.0};  // of the last three iterates
  // The first pass always builds the Jacobian; later passes first check convergence with the
  // cheap residual-only evaluation and build the Jacobian only if another update needs a fresh
  // one.
  for (int iter = 0; iter <= options_.max_iterations; ++iter) {
    transportInto(q, start.frames, frames);
    bool built = iter == 0;
    attempt.residual = evaluate(start, q, dt, frames, built);
    attempt.iterations = iter;
    if (options_.trace)
      std::fprintf(stderr, "t=%.4f iter %d residual %.3e%s\n", start.time, iter, attempt.residual,
                   last_update_chord ? " (chord)" : "");
    const double previous_residual = residual_history[(iter + 2) % 3];  // of iterate iter - 1
    if (last_update_chord && !(attempt.residual < previous_residual)) {
      // The chord update raised the residual: undo it and rebuild the Jacobian there.
      q = previous_iterate_;
      transportInto(q, start.frames, frames);
      attempt.residual = evaluate(start, q, dt, frames, true);
      built = true;
    } else {
      if (!std::isfinite(attempt.residual)) return failed("a non-finite residual");
      if (attempt.residual < options_.residual_tolerance) {
        accept();
        return attempt;
      }
      if (iter == options_.max_iterations) return failed("no convergence within max_iterations");
    }
    residual_history[iter % 3] = attempt.residual;
    // Plain Newton that has stopped converging (a two-cycle) gives up early when the damped
    // retry is there to take over.
    if (!damped && options_.damped_retry && iter >= kStagnationCheckStart &&
        attempt.residual > kStagnationResidualFactor * options_.residual_tolerance &&
        attempt.residual > kStagnationRatio * residual_history[(iter + 1) % 3])
      return failed("stagnation (residual not halved in two updates)");
    VecX& dq = update_;
    if (krylov_attempt_) {
      if (!built) evaluate(start, q, dt, frames, true);
      if (!krylovUpdate(start, q, dt, frames)) return failed("a singular Jacobian");
      last_update_chord = false;
    } else {
      // (Past the first pass a factored Jacobian always exists: a failed factorization returns.)
      const bool chord = !built && !damped &&
                         attempt.residual < options_.jacobian_reuse * previous_residual &&
                         attempt.residual < kChordResidualFactor * options_.residual_tolerance;
      if (!chord && !factorAt(start, q, dt, frames, built)) return failed("a singular Jacobian");
      last_update_chord = chord;
      solveJacobian(residual_, dq);
    }
    if (!dq.allFinite()) return failed("a non-finite update");
    bool round_off;
    {
      ProfileScope timer(profile_, &StepProfile::convergence);
      round_off = stepNorm(dq) < options_.step_tolerance &&
                  attempt.residual < kStagnationResidualFactor * options_.residual_tolerance;
    }
    // A round-off-level update needs no line search: the residual cannot descend further.
    if (damped && !round_off) {
      double length = 1.0;
      for (int k = 0;; ++k) {
        const VecX trial = q - length * dq;
        transportInto(trial, start.frames, trial_frames_);
        const double r = evaluate(start, trial, dt, trial_frames_, false);
        if (r < (1.0 - kArmijoFraction * length) * attempt.residual) break;
        if (k == kMaxBacktracks) return failed("no descent along the Newton direction");
        length *= 0.5;
      }
      dq *= length;
    }
    if (last_update_chord) previous_iterate_ = q;
    q -= dq;
    if (round_off) {
      // Round-off-level update with a nearly converged residual: accept (NewtonOptions).
      transportInto(q, start.frames, frames);
      accept();
      return attempt;
    }
  }
  return failed("no convergence within max_iterations");
}

std::string ImplicitStepper::foldedJointNote(const RodState& state) const {
  // no step size passes a joint folded back on itself (docs/model.md 1.3)
  const FoldedJoint joint = mostFoldedJoint(net_, state.frames);
  if (joint.spring < 0 || joint.angle < kFoldedJointAngle) return "";
  std::ostringstream note;
  note << "; the joint at node " << net_.bend_twist_springs[joint.spring].node_c
       << (joint.spring == net_.parts.motor_spring ? " (the motor joint)" : "") << " is folded to "
       << joint.angle * 180.0 / M_PI << " deg, where the discrete curvature diverges";
  return note.str();
}

StepReport ImplicitStepper::stepRecursive(RodState& state, double dt, Motor& motor, int depth) {
  while (static_cast<int>(trial_states_.size()) <= depth) trial_states_.emplace_back();
  RodState& trial = trial_states_[depth];  // storage reused; solveStep writes q, qdot, frames
  const double t_next = state.time + dt;
  // Effect hooks of this (sub)step: viscosity factor (product) and motor speed (chained).
  double viscosity_factor = 1.0;
  for (const EffectPtr& e : effects_) viscosity_factor *= e->viscosityFactor(t_next);
  const double viscosity = medium_.viscosity() * viscosity_factor;
  const double command = motor.commandAt(t_next);
  double omega = command;
  if (motor.needsLoad() && std::isfinite(command))
    omega = motor.speed(command, motorLoad(state, command, t_next));
  if (!std::isfinite(omega)) {
    std::ostringstream msg;
    msg << "motor " << (std::isfinite(command) ? "speed" : "command") << " is not finite (" << omega
        << ") at t = " << t_next << " s";
    throw SolverFailure(msg.str());
  }
  const StepStart start{net_, state, dt, medium_, viscosity};
  {
    ProfileScope timer(profile_, &StepProfile::effects);
    for (const EffectPtr& e : effects_) e->beginStep(start);
  }
  // docs/model.md 1.9: tau_bar(t_{k+1}) = tau_bar(t_k) + omega(t_{k+1}) dt (fully implicit)
  const double offset = state.motor_twist_offset + omega * dt;
  Attempt a = solveStep(state, trial, dt, offset, viscosity, false);
  int damped_retries = 0;
  if (!a.converged && options_.damped_retry) {
    const Attempt plain = a;
    a = solveStep(state, trial, dt, offset, viscosity, true);
    a.iterations += plain.iterations;
    damped_retries = a.converged ? 1 : 0;
  }
  if (a.converged) {
    trial.time = t_next;
    trial.motor_twist_offset = offset;
    {
      ProfileScope timer(profile_, &StepProfile::effects);
      for (const EffectPtr& e : effects_) e->acceptStep(net_, state, trial);
    }
    motor.recordApplied(command, omega);
    viscosity_factor_ = viscosity_factor;
    std::swap(state, trial);  // trial keeps the old state's storage for the next step
    return {a.iterations, 1, a.residual, damped_retries};
  }
  if (depth >= options_.max_subdivision_depth) {
    std::ostringstream msg;
    msg << "Newton did not converge at t = " << state.time << " s with dt = " << dt << " s after "
        << depth << " subdivisions (scaled residual " << a.residual << ", tolerance "
        << options_.residual_tolerance << "; the last attempt ended on " << a.failure << ")"
        << foldedJointNote(state);
    throw SolverFailure(msg.str());
  }
  RodState half = state;
  StepReport first = stepRecursive(half, 0.5 * dt, motor, depth + 1);
  StepReport second = stepRecursive(half, 0.5 * dt, motor, depth + 1);
  state = std::move(half);
  return {a.iterations + first.newton_iterations + second.newton_iterations,
          first.substeps + second.substeps, second.residual,
          first.damped_retries + second.damped_retries};
}

StepReport ImplicitStepper::step(RodState& state, double dt, Motor& motor) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream msg;
    msg << "time step must be > 0 and finite, got " << dt;
    throw SolverFailure(msg.str());
  }
  // What a failed step must put back besides `state`: sub-steps accepted before the failure
  // have already advanced the effects' internal state and the motor's record.
  std::vector<std::vector<double>>& effect_states = saved_effect_states_;
  effect_states.resize(effects_.size());
  for (size_t i = 0; i < effects_.size(); ++i) effect_states[i] = effects_[i]->internalState();
  const double viscosity_factor = viscosity_factor_;
  const Motor::Record motor_record = motor.record();
  auto restore = [&] {
    for (size_t i = 0; i < effects_.size(); ++i) effects_[i]->setInternalState(effect_states[i]);
    viscosity_factor_ = viscosity_factor;
    motor.restore(motor_record);
  };
  ProfileScope timer(profile_, &StepProfile::total);
  if (profile_) ++profile_->steps;
  try {
    return stepRecursive(state, dt, motor, 0);  // assigns state only when the whole step succeeded
  } catch (const SolverFailure& e) {
    restore();
    std::ostringstream msg;
    msg << "step from t = " << state.time << " s with dt = " << dt << " s failed: " << e.what();
    throw SolverFailure(msg.str());
  } catch (...) {  // e.g. an effect's parameters out of their domain at this time
    restore();
    throw;
  }
}

StepReport ImplicitStepper::step(RodState& state, double dt, const MotorCommand& schedule) {
  Motor motor(std::shared_ptr<const MotorCommand>(&schedule, [](const MotorCommand*) {}));
  motor.setSpeedLaws(motorSpeedLaws());
  return step(state, dt, motor);
}

MotorLoad ImplicitStepper::motorLoad(const RodState& state, double omega_cmd,
                                     double time_next) const {
  MotorLoad load;
  load.time = time_next;
  const int index = net_.parts.motor_spring;
  if (index < 0) return load;
  // natural twist at t_k
  const BendTwistSpring spring =
      drivenSpring(net_, {index, motor_tau_bar0_ + state.motor_twist_offset});
  const SpringEnergyTerms terms =
      bendTwistTerms(springGeometry(net_, spring, state.q, state.frames, index), spring, false);
  const SpringDofMap map = springDofMap(net_, spring);
  const int head_theta = net_.thetaIndex(net_.parts.head_edge);
  for (int a = 9; a < 11; ++a)  // the spring's local twist DOFs (docs/model.md 1.6)
    if (map.index[a] == head_theta) load.head_moment -= map.sign[a] * terms.gradient(a);
  load.torque = (omega_cmd >= 0.0 ? -1.0 : 1.0) * load.head_moment;  // along the command
  return load;
}

}  // namespace flagella
