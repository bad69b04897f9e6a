// Fully implicit Euler step solved by Newton-Raphson on a sparse, generally non-symmetric
// Jacobian (spec 1.10). The sparsity pattern and the LU symbolic analysis are reused across
// iterations and steps. Failure strategy: a step whose Newton iteration does not converge (too
// many iterations, a singular Jacobian, or a non-finite value) is retried once with a
// backtracking line search (NewtonOptions::damped_retry), then as two half steps, recursively up
// to NewtonOptions::max_subdivision_depth; if that fails too, SolverFailure is thrown and the
// state is left at the last accepted step.
#pragma once

#include <memory>
#include <stdexcept>
#include <vector>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/effects/effect.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"
#include "flagella_sim/solver/newton_options.h"
#include "flagella_sim/solver/sparse_lu_solver.h"

namespace flagella {

class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StepReport {
  int newton_iterations = 0;  ///< summed over sub-steps
  int substeps = 1;           ///< 1 unless the step had to be subdivided
  double residual = 0.0;      ///< scaled residual at the end of the last sub-step
  int damped_retries = 0;     ///< (sub)steps solved only by the line-search retry
};

class ImplicitStepper {
 public:
  ImplicitStepper(RodNetwork net, std::vector<EffectPtr> effects, Medium medium,
                  NewtonOptions options);

  /// State at t = 0: rest configuration, zero rates, space-parallel frames.
  RodState initialState() const;

  /// Advances state by dt with the motor speed from `motor`. Throws SolverFailure if the
  /// step cannot be completed even after subdivision; state is then unchanged (and so are the
  /// network's motor twist and the effects' internal state, whatever the exception).
  /// Before every (sub)step the effects' hooks set the medium's viscosity factor and shape the
  /// motor speed (Effect::viscosityFactor, Effect::motorSpeed); after every accepted (sub)step
  /// Effect::acceptStep is called.
  StepReport step(RodState& state, double dt, const MotorCommand& motor);

  /// The motor's load at `state` (the start of a step) for a command `omega_cmd` (spec 1.9):
  /// the motor spring's generalised force on theta^0, with the natural twist of that state.
  MotorLoad motorLoad(const RodState& state, double omega_cmd, double time_next) const;
  /// Motor speed applied to the natural twist in the last accepted (sub)step [rad/s]: the
  /// command unless an effect (dc_motor) modifies it.
  double lastMotorSpeed() const { return last_motor_speed_; }

  const RodNetwork& network() const { return net_; }
  RodNetwork& network() { return net_; }
  Medium& medium() { return medium_; }
  const Medium& medium() const { return medium_; }
  const std::vector<EffectPtr>& effects() const { return effects_; }
  Effect* findEffect(const std::string& name) const;
  NewtonOptions& options() { return options_; }
  int totalFactorizations() const { return factorizations_; }
  int totalAnalyses() const { return analyses_; }
  const SparseLuSolver& linearSolver() const { return lu_; }

 private:
  struct Attempt {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0;
  };
  /// One Newton solve of the step; `damped`: backtrack each update until the scaled residual
  /// decreases (Armijo), and give up if no step length below 1 decreases it.
  Attempt solveStep(RodState& state, double dt, double motor_offset, bool damped);
  /// Fills residual_ (and the Jacobian in assembler_ if asked) at iterate q; returns the
  /// scaled residual (infinity if anything is not finite).
  double evaluate(const RodState& start, const VecX& q, double dt, const ReferenceFrames& frames,
                  bool with_jacobian);
  StepReport stepRecursive(RodState& state, double dt, const MotorCommand& motor, int depth);
  double scaledResidual(const VecX& f) const;
  double stepNorm(const VecX& dq) const;
  void pinFixedDofs(SparseMatrix& J) const;

  RodNetwork net_;
  std::vector<EffectPtr> effects_;
  Medium medium_;
  NewtonOptions options_;
  double motor_tau_bar0_ = 0.0;
  double last_motor_speed_ = 0.0;
  bool any_fixed_ = false;
  bool any_motor_shaping_ = false;  ///< some effect overrides Effect::motorSpeed
  SparseAssembler assembler_;
  VecX residual_, external_;
  SparseLuSolver lu_;
  bool analyzed_ = false;
  int factorizations_ = 0;
  int analyses_ = 0;
};

}  // namespace flagella
