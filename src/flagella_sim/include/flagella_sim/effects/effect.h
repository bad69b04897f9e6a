// The plug-in interface every external physics term implements: add your generalised force
// and its exact Jacobian to the system, declare your named parameters (architecture.md).
#pragma once

#include <memory>
#include <string>

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
  const ReferenceFrames& frames;  ///< frames at q
  const VecX& q_start;            ///< q(t_k)
  const VecX& qdot_start;         ///< qdot(t_k)
  double dt = 0.0;
  double time = 0.0;  ///< t_{k+1}
  const Medium& medium;

  /// Implicit velocity of DOF i: (q_i - q_i(t_k))/dt (spec 1.10).
  double rate(int i) const { return (q(i) - q_start(i)) / dt; }
  Vec3 nodeVelocity(int node) const {
    return (q.segment<3>(3 * node) - q_start.segment<3>(3 * node)) / dt;
  }
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

class Effect {
 public:
  explicit Effect(std::string name) : name_(std::move(name)) {}
  virtual ~Effect() = default;
  const std::string& name() const { return name_; }
  ParameterSet& parameters() { return params_; }
  const ParameterSet& parameters() const { return params_; }

  /// Called once when the effect is attached to a network (precompute node lists etc.).
  virtual void attach(const RodNetwork& /*net*/) {}
  /// Adds the generalised external force F(q, (q - q_k)/dt) to `force` and, when `jacobian`
  /// is non-null, dF/dq. The sequence of Jacobian entries must not depend on the values.
  virtual void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const = 0;

 protected:
  ParameterSet params_;

 private:
  std::string name_;
};

using EffectPtr = std::unique_ptr<Effect>;

}  // namespace flagella
