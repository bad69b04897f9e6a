// Nonlocal hydrodynamics of the flagellum by regularized Stokeslet segments (docs/model.md 4):
// the RSS matrix of the tail nodes is built and factored once per step at x(t_k); the force is
// F^hyd = -K (x - x(t_k))/dt with K = 8 pi mu D Ablk^{-1} (one LU solve per evaluation) and the
// dense Jacobian block -K/dt, handed to the stepper as Ablk and D so that K is never formed
// (option B, implicit, the default), or F^hyd = -K xdot(t_k) held fixed over the step with no
// Jacobian (option A, explicit) (docs/model.md 4.4).
#pragma once

#include <optional>
#include <vector>

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"
#include "flagella_sim/hydro/rss_solver.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& rssHydrodynamicsEffect();

class RssHydrodynamics : public Effect, public ForceLaw, public StepHooks {
 public:
  static constexpr const char* kName = "rss";
  /// `filament_radius`: r0 [m] (eps = eps_ratio r0 until eps itself is set); `implicit`: option B
  /// (else option A).
  RssHydrodynamics(double filament_radius, bool implicit);
  void attach(const RodNetwork& net) override;
  void beginStep(const StepStart& start) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;
  bool hasDenseJacobian() const override { return implicit_; }
  void addDenseJacobian(const EffectContext& ctx, DenseJacobianSink& sink) const override;

  /// Network nodes the RSS acts on (every tail chain, root first), in system order.
  const std::vector<int>& nodes() const { return nodes_; }
  /// (Sub)steps since the first, and how many of them reused the factored matrix rotated.
  long stepsAfterFirst() const { return steps_; }
  long reusedSteps() const { return reused_; }

 private:
  VecX gather(const VecX& q) const;  ///< the RSS nodes' positions (3M) from a DOF vector
  /// eps for this step: eps_ratio r0 or eps, whichever was set last (eps kept in step with it).
  double currentEps();

  int eps_ = 0, eps_ratio_ = 0, reuse_tolerance_ = 0;
  long steps_ = 0, reused_ = 0;
  bool implicit_ = true;
  bool relative_ = true;
  double filament_radius_ = 0.0;
  double last_eps_ = 0.0, last_ratio_ = 0.0;
  std::vector<int> nodes_;
  std::vector<int> dofs_;  ///< 3 position DOFs per RSS node
  rss::Segments segments_;
  std::optional<rss::RssSolver> solver_;  ///< Ablk at x(t_k), factored (option B)
  VecX explicit_force_;                   ///< -K xdot(t_k) (option A)
};

}  // namespace flagella
