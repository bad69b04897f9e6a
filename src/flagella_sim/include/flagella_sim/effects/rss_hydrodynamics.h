// Nonlocal hydrodynamics of the flagellum by regularized Stokeslet segments (docs/model.md 4):
// the RSS matrix of the tail nodes is built once per step at x(t_k); the force is
// F^hyd = -K (x - x(t_k))/dt with K = 8 pi mu D Ablk^{-1} and the dense Jacobian block -K/dt,
// handed to the stepper as Ablk and D so that K is never formed (option B, implicit, the
// default), or F^hyd = -K xdot(t_k) held fixed over the step with no Jacobian (option A,
// explicit) (docs/model.md 4.4). Option B follows the Newton-Krylov iterates by their preimages
// g = Ablk^{-1} (x - x(t_k)) (MappedIterates) and predicts each step's first iterate from the
// last two steps' g, so that a step needs no LU of Ablk; any other iterate takes one LU solve
// (the LU made when first needed).
#pragma once

#include <optional>
#include <vector>

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"
#include "flagella_sim/hydro/rss_solver.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& rssHydrodynamicsEffect();

class RssHydrodynamics : public Effect, public ForceLaw, public StepHooks, public MappedIterates {
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
  void acceptStep(const RodNetwork& net, const RodState& start, const RodState& end) override;
  void predictIterate(const RodState& start, double dt, VecX& q) override;
  void noteMappedUpdate(const VecX& previous, const VecX& q, const VecX& preimage,
                        const FactoredMatrix* mapped, double scale) override;

  /// Network nodes the RSS acts on (every tail chain, root first), in system order.
  const std::vector<int>& nodes() const { return nodes_; }
  /// (Sub)steps since the first, and how many of them reused the factored matrix rotated.
  long stepsAfterFirst() const { return steps_; }
  long reusedSteps() const { return reused_; }
  /// Force evaluations that needed a solve with Ablk (the others used a followed preimage).
  long forceSolves() const { return force_solves_; }

 private:
  VecX gather(const VecX& q) const;  ///< the RSS nodes' positions (3M) from a DOF vector
  /// g = Ablk^{-1} (x - x_k) at the RSS positions x: the followed one if x is the followed
  /// iterate, else solved (and followed from then on).
  const VecX& preimageAt(const VecX& x, const VecX& q_start) const;

  // The followed iterate (docs/model.md 4.4): RSS positions and their preimage g.
  mutable VecX followed_x_, followed_g_;
  mutable bool following_ = false;
  mutable long force_solves_ = 0;
  // g of the last two accepted (sub)steps, for the predictor: valid while the steps chain.
  struct StepPreimage {
    VecX g;
    double start = 0.0, end = 0.0, dt = 0.0;
    bool valid = false;
  };
  StepPreimage last_, before_last_;
  double step_dt_ = 0.0;
  bool any_fixed_ = false;  ///< an RSS DOF is pinned: no prediction
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
