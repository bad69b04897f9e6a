// The plug-in interface of every external physics term: an Effect (name and named parameters)
// that plays one or more roles: a force (residual and exact Jacobian), a motor speed law, a
// viscosity law, per-step hooks (architecture.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/core/factored_matrix.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/types.h"
#include "flagella_sim/effects/medium.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

/// What an effect sees during one Newton iterate of the step t_k -> t_{k+1}.
struct EffectContext {
  const RodNetwork& net;
  const VecX& q;                  ///< current iterate of q(t_{k+1})
  const ReferenceFrames& frames;  ///< frames at q (their tangents and edge lengths are q's)
  const VecX& q_start;            ///< q(t_k)
  const VecX& qdot_start;         ///< qdot(t_k)
  double dt = 0.0;
  double time = 0.0;  ///< t_{k+1}
  const Medium& medium;
  /// Viscosity during this (sub)step [Pa s]: the medium's mu0 times the effects' factors.
  double viscosity;

  /// Implicit velocity of DOF i: (q_i - q_i(t_k))/dt (docs/model.md 1.10).
  double rate(int i) const { return (q(i) - q_start(i)) / dt; }
  Vec3 nodeVelocity(int node) const {
    return (q.segment<3>(3 * node) - q_start.segment<3>(3 * node)) / dt;
  }
};

/// The motor's load at the start of a step, for effects that shape the applied motor speed
/// (docs/model.md 1.9). One-step lag: it is evaluated at q(t_k), so the speed of the step t_k ->
/// t_{k+1} does not depend on the unknown q(t_{k+1}).
struct MotorLoad {
  double head_moment = 0.0;  ///< generalised force of the motor spring alone on theta^0 [N m]
  /// Load torque along the sign of the command, -sign(omega_cmd) head_moment [N m]: positive
  /// when the motor works against the head drag (sign(0) = +1).
  double torque = 0.0;
  double time = 0.0;  ///< t_{k+1}
};

/// Receives dF/dq entries; the stepper subtracts them from the Newton Jacobian.
class JacobianSink {
 public:
  virtual ~JacobianSink() = default;
  virtual void add(int row, int col, double value) = 0;
  virtual void addBlock(int row, int col, const Mat3& block) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) add(row + a, col + b, block(a, b));
  }
};

/// Receives a dense block of dF/dq (docs/model.md 4.4 option B); the stepper subtracts it from
/// the Newton Jacobian and then solves the Newton system with a dense LU.
class DenseJacobianSink {
 public:
  virtual ~DenseJacobianSink() = default;
  /// Adds scale * block to dF/dq at rows and columns `dofs` (block is dofs.size() squared).
  virtual void addDense(const std::vector<int>& dofs, const MatX& block, double scale) = 0;
  /// Adds scale * diag(row_weights) * A^{-1} at rows and columns `dofs`, A given with its
  /// factorisation. The stepper's sink never forms the inverse (solver/dense_newton_system.h);
  /// this default does. `a` must stay unchanged until the effect's next beginStep.
  virtual void addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a,
                                const VecX& row_weights, double scale) {
    addDense(dofs, row_weights.asDiagonal() * a.inverse(), scale);
  }
};

/// The start of a (sub)step t_k -> t_k + dt, before its Newton solve.
struct StepStart {
  const RodNetwork& net;
  const RodState& state;  ///< at t_k
  double dt = 0.0;
  const Medium& medium;
  double viscosity;  ///< of the (sub)step [Pa s], as EffectContext::viscosity
};

/// The roles an effect can play (docs/architecture.md, "Effects"); an effect class derives from
/// Effect and from each role it plays, and the stepper finds the roles once (Effect::as).

/// A generalised external force: its residual and exact Jacobian.
class ForceLaw {
 public:
  virtual ~ForceLaw() = default;
  /// Adds the generalised external force F(q, (q - q_k)/dt) to `force` and, when `jacobian`
  /// is non-null, dF/dq. The sequence of Jacobian entries must not depend on the values.
  virtual void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const = 0;
  /// True for forces whose Jacobian has a dense block (addDenseJacobian); the stepper then
  /// solves the Newton system with a dense LU instead of the sparse one.
  virtual bool hasDenseJacobian() const { return false; }
  /// Adds the dense part of dF/dq at the iterate (called whenever the Jacobian is built).
  virtual void addDenseJacobian(const EffectContext& /*ctx*/, DenseJacobianSink& /*sink*/) const {}
};

/// A torque-speed law of the motor (docs/model.md 1.9). The motor chains the laws in the order
/// the effects are listed (each scales the speed the previous one returned); the stepper
/// evaluates the motor's load (one spring's bending-twisting terms per step) only when some
/// effect has this role.
class MotorSpeedLaw {
 public:
  virtual ~MotorSpeedLaw() = default;
  /// The speed applied to the natural twist during the (sub)step ending at load.time, given the
  /// speed `omega` requested upstream (the command, or the previous law's result) [rad/s].
  virtual double motorSpeed(double omega, const MotorLoad& load) const = 0;
};

/// A slow change of the medium's viscosity (effect-owned state of a time-varying medium).
class ViscosityLaw {
 public:
  virtual ~ViscosityLaw() = default;
  /// Multiplier on the medium's configured viscosity during the (sub)step ending at `time`
  /// (t_{k+1}). The stepper passes the product over all laws to every effect as
  /// EffectContext::viscosity (the Medium stays constant).
  virtual double viscosityFactor(double time) const = 0;
};

/// A force of the form F = -diag(w) A^{-1} (x - x_k) / dt whose Jacobian block the Newton system
/// right-preconditions by A (DenseNewtonSystem: updates dq = C z, C = A / alpha on the force's
/// DOFs). Such a force can follow the Newton iterates by their preimages, g = A^{-1} (x - x_k),
/// so that its residual needs no solve with A (docs/model.md 4.4); the stepper calls these in
/// its Newton-Krylov attempts only. Iterates reached any other way are not followed.
class MappedIterates {
 public:
  virtual ~MappedIterates() = default;
  /// May set the force's DOFs of the first iterate `q` (the stepper's predictor set them all)
  /// from its own history, which it then follows.
  virtual void predictIterate(const RodState& start, double dt, VecX& q) = 0;
  /// The iterate `previous` became `q` by q = previous - C z, z = `preimage`, C mapping by
  /// `mapped` (alpha = `scale`).
  virtual void noteMappedUpdate(const VecX& previous, const VecX& q, const VecX& preimage,
                                const FactoredMatrix* mapped, double scale) = 0;
};

/// Per-step hooks: what a force holds fixed over a step, and internal state carried between
/// steps. The defaults do nothing.
class StepHooks {
 public:
  virtual ~StepHooks() = default;
  /// Called before the Newton solve of every (sub)step: the place to build what the step
  /// holds fixed, e.g. the RSS matrix at x(t_k) (docs/model.md 4.4). Throwing here fails the
  /// step like an effect out of its domain.
  virtual void beginStep(const StepStart& /*start*/) {}
  /// Called after every accepted (sub)step with the states at its start and end: the place to
  /// update internal state (e.g. hysteresis). Not called for rejected attempts.
  virtual void acceptStep(const RodNetwork& /*net*/, const RodState& /*start*/,
                          const RodState& /*end*/) {}
  /// Internal state changed by acceptStep, saved by the stepper before a step and restored if
  /// the step fails, so a failed step leaves the effect as it was.
  virtual std::vector<double> internalState() const { return {}; }
  virtual void setInternalState(const std::vector<double>& /*state*/) {}
};

/// What the registry builds and a config switches on: a name, named parameters, and the roles
/// above that the effect's class also derives from.
class Effect {
 public:
  /// Declares the parameters of `schema` (an effect's descriptor) with their defaults and ranges.
  explicit Effect(std::string name, const std::vector<ParameterSpec>& schema = {})
      : name_(std::move(name)) {
    for (const ParameterSpec& p : schema)
      params_.declare(p.name, p.value, p.min, p.max, p.unit, p.description);
  }
  virtual ~Effect() = default;
  const std::string& name() const { return name_; }
  ParameterSet& parameters() { return params_; }
  const ParameterSet& parameters() const { return params_; }

  /// Called once when the effect is attached to a network (precompute node lists etc.).
  virtual void attach(const RodNetwork& /*net*/) {}

  /// This effect in role `Role` (ForceLaw, MotorSpeedLaw, ViscosityLaw, StepHooks), or nullptr.
  template <class Role>
  Role* as() {
    return dynamic_cast<Role*>(this);
  }
  template <class Role>
  const Role* as() const {
    return dynamic_cast<const Role*>(this);
  }

 protected:
  /// Index of a parameter declared from the schema (for fast access in addForce).
  int parameterIndex(const std::string& name) const { return params_.index(name); }
  /// parameterIndex, after setting the parameter to `value` (a default that depends on the
  /// robot or the medium); out of range throws naming the effect's parameter.
  int parameterIndex(const std::string& name, double value) {
    params_.set(name, value, name_);
    return params_.index(name);
  }
  ParameterSet params_;

 private:
  std::string name_;
};

using EffectPtr = std::unique_ptr<Effect>;

}  // namespace flagella
