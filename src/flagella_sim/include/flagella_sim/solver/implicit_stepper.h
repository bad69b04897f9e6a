// Fully implicit Euler step solved by Newton-Raphson on a sparse, generally non-symmetric
// Jacobian (docs/model.md 1.10). The sparsity pattern and the LU symbolic analysis are reused
// across iterations and steps. Failure strategy: a step whose Newton iteration does not converge
// (too many iterations, a singular Jacobian, or a non-finite value) is retried once with a
// backtracking line search (NewtonOptions::damped_retry), then as two half steps, recursively up
// to NewtonOptions::max_subdivision_depth; if that fails too, SolverFailure is thrown and the
// state is left at the last accepted step.
// Linear solve: a sparse 4x4-block LU with KLU as its fallback (JacobianSolver), or a dense
// partial-pivot LU of the whole Jacobian when an effect has a dense Jacobian block
// (ForceLaw::hasDenseJacobian, the RSS hydrodynamics of docs/model.md 4.4), right-preconditioned so
// that the RSS drag is never inverted (DenseNewtonSystem).
#pragma once

#include <deque>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor.h"
#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/effects/effect.h"
#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"
#include "flagella_sim/solver/dense_jacobian_product.h"
#include "flagella_sim/solver/dense_newton_system.h"
#include "flagella_sim/solver/gmres.h"
#include "flagella_sim/solver/jacobian_solver.h"
#include "flagella_sim/solver/newton_options.h"
#include "flagella_sim/solver/solver_failure.h"
#include "flagella_sim/solver/step_profile.h"

namespace flagella {

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

  /// Advances state by dt with the natural-twist rate from `motor`. Throws SolverFailure if the
  /// step cannot be completed even after subdivision; state is then unchanged (and so are the
  /// motor's record and the effects' internal state, whatever the exception).
  /// Before every (sub)step the effects give the viscosity factor (ViscosityLaw::viscosityFactor,
  /// passed to the effects as EffectContext::viscosity) and the motor its speed; after every
  /// accepted (sub)step StepHooks::acceptStep is called and the motor records what it applied.
  StepReport step(RodState& state, double dt, Motor& motor);
  /// The same with a one-step motor that follows `schedule` with this stepper's torque-speed
  /// laws (its record is discarded): for stepper-level tests without a Simulation.
  StepReport step(RodState& state, double dt, const MotorCommand& schedule);

  /// The effects whose torque-speed law shapes the motor speed (role MotorSpeedLaw), in order.
  std::vector<const MotorSpeedLaw*> motorSpeedLaws() const { return speed_laws_; }
  /// Viscosity of the last accepted (sub)step: medium mu0 times the effects' factors [Pa s].
  double currentViscosity() const { return medium_.viscosity() * viscosity_factor_; }

  const RodNetwork& network() const { return net_; }
  RodNetwork& network() { return net_; }
  const Medium& medium() const { return medium_; }
  /// The medium's named parameters ("medium.viscosity"): set between steps, never by a step.
  ParameterSet& mediumParameters() { return medium_.parameters(); }
  const std::vector<EffectPtr>& effects() const { return effects_; }
  Effect* findEffect(const std::string& name) const;
  /// The effect of class T (found by its registry name T::kName), or nullptr if not configured.
  template <class T>
  T* findEffect() const {
    return dynamic_cast<T*>(findEffect(T::kName));
  }
  NewtonOptions& options() { return options_; }
  int totalFactorizations() const { return factorizations_; }
  int totalAnalyses() const { return analyses_; }
  /// True when the Newton system is solved densely (an effect has a dense Jacobian block).
  bool denseLinearSolve() const { return dense_; }
  const JacobianSolver& linearSolver() const { return lu_; }
  /// Times the parts of every later step into `profile` (not owned; null stops profiling).
  void setProfile(StepProfile* profile) { profile_ = profile; }

 private:
  struct Attempt {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0;
    const char* failure = "";     ///< why an attempt that did not converge ended
    bool damped_retried = false;  ///< this is the damped retry of a failed plain attempt
    Attempt& fail(const char* reason) {
      failure = reason;
      return *this;
    }
  };
  /// What the Newton iteration of an attempt carries from one iterate to the next.
  struct NewtonProgress {
    /// The last update reused the factored Jacobian (NewtonOptions::jacobian_reuse).
    bool last_update_chord = false;
    /// Scaled residuals of the last kHistory iterates (NewtonOptions::stagnation_updates looks
    /// back at most 12 updates).
    static constexpr int kHistory = 16;
    static_assert(NewtonOptions::kMaxStagnationUpdates < kHistory);
    double residuals[kHistory] = {};
    /// Of iterate `iter` (one of the last kHistory: iter >= current iterate - kHistory + 1).
    double residualOf(int iter) const { return residuals[(iter + kHistory) % kHistory]; }
    void record(int iter, double residual) { residuals[iter % kHistory] = residual; }
  };
  enum class IterateVerdict { kConverged, kFailed, kUpdate };
  /// What drives a (sub)step ending at t_next: the effects' viscosity and the motor's speed.
  struct SubstepDrive {
    double viscosity_factor = 1.0;  ///< product of the effects' factors
    double viscosity = 0.0;         ///< [Pa s]
    MotorDrive motor;               ///< the motor's command, speed and natural twist
  };

  /// One Newton solve of the step; `damped`: backtrack each update until the scaled residual
  /// decreases (Armijo), and give up if no step length below 1 decreases it.
  /// The step from `start`; a converged attempt writes q, qdot and frames of `result` (nothing
  /// else), a failed one leaves it as it was.
  Attempt solveStep(const RodState& start, RodState& result, double dt, double motor_offset,
                    double viscosity, bool damped);
  /// Sets what evaluate() uses for this attempt: motor twist, viscosity, dt, Newton-Krylov.
  void beginAttempt(double dt, double motor_offset, double viscosity, bool damped);
  /// Writes the initial Newton iterate of the step from `start` into q (docs/model.md 1.10).
  void setInitialGuess(const RodState& start, double dt, VecX& q) const;
  /// Evaluates iterate `iter` at iterate_ (undoing a chord update that raised the residual) and
  /// tests it: converged, failed (attempt.failure says why) or in need of an update. `built`:
  /// the Jacobian at iterate_ was built by that evaluation.
  IterateVerdict testIterate(const RodState& start, double dt, int iter, NewtonProgress& progress,
                             Attempt& attempt, bool& built);
  /// Plain Newton that has stopped converging (a two-cycle), with the damped retry to take over.
  bool isStagnating(int iter, double residual, const NewtonProgress& progress, bool damped) const;
  /// The Newton update at iterate_ into update_ (fresh, chord or Newton-Krylov); null, or why
  /// the attempt fails.
  const char* computeUpdate(const RodState& start, double dt, int iter, double residual, bool built,
                            bool damped, NewtonProgress& progress);
  /// A round-off-level update with a nearly converged residual (NewtonOptions::step_tolerance).
  bool isRoundOffUpdate(const VecX& dq, double residual) const;
  /// Damped retry: shortens update_ until the scaled residual at iterate_ - update_ descends
  /// (Armijo); false if no step length does.
  bool backtrackUpdate(const RodState& start, double dt, double residual);
  /// A converged attempt: writes q, qdot and frames of `result`, and the predictor's history.
  void acceptAttempt(const RodState& start, RodState& result, double dt, Attempt& attempt);
  /// Fills residual_ (and the Jacobian in assembler_ if asked) at iterate q; returns the
  /// scaled residual (infinity if anything is not finite).
  double evaluate(const RodState& start, const VecX& q, double dt, const ReferenceFrames& frames,
                  bool with_jacobian);
  /// A (sub)step at subdivision depth `depth`: the plain attempt, the damped retry, then two
  /// half steps; assigns state only when it succeeded.
  StepReport stepRecursive(RodState& state, double dt, Motor& motor, int depth);
  /// The viscosity and the motor's drive (Motor::drive) of the (sub)step of length `dt` from
  /// `state` to t_next; throws SolverFailure when the motor's command or speed is not finite.
  SubstepDrive substepDrive(const RodState& state, double t_next, double dt,
                            const Motor& motor) const;
  /// The plain attempt and, if it fails, the damped retry (NewtonOptions::damped_retry).
  Attempt solveWithDampedRetry(const RodState& start, RodState& result, double dt,
                               double motor_offset, double viscosity);
  /// An accepted (sub)step: the effects' and the motor's records; `trial` becomes `state`.
  void acceptSubstep(RodState& state, RodState& trial, double t_next, const SubstepDrive& drive,
                     Motor& motor);
  /// The step from `state` as two half steps one level deeper (`failed_iterations`: spent on the
  /// failed attempts at this level).
  StepReport subdivide(RodState& state, double dt, Motor& motor, int depth, int failed_iterations);
  /// Why a (sub)step at the deepest subdivision failed, for SolverFailure.
  std::string nonConvergenceMessage(const RodState& state, double dt, int depth,
                                    const Attempt& attempt) const;
  /// "; the joint at node N ... is folded to X deg ..." when a bending spring of `state` is
  /// folded nearly back on itself (the usual cause of a step no subdivision passes), else "".
  std::string foldedJointNote(const RodState& state) const;
  double scaledResidual(const VecX& f) const;
  double stepNorm(const VecX& dq) const;
  void pinFixedDofs(SparseMatrix& J) const;
  /// Hands every effect's dense Jacobian blocks at `ctx` to `sink`.
  void addDenseBlocks(const EffectContext& ctx, DenseJacobianSink& sink) const;
  /// Starts the dense Newton system from the sparse Jacobian and adds the effects' dense blocks.
  void buildDenseJacobian(const EffectContext& ctx);
  enum class Factorization {
    kFactored,
    kSingular,
    kNeedsMatrix,  ///< the block LU refused a Jacobian assembled in place: assemble it again
  };
  /// Factors the Jacobian built by evaluate(); klu_only: with KLU, not trying the block LU.
  Factorization factorizeJacobian(bool klu_only = false);
  /// Factors the Jacobian at q (evaluating it first unless `built`: evaluate() just built it
  /// there); false if it is singular.
  bool factorAt(const RodState& start, const VecX& q, double dt, const ReferenceFrames& frames,
                bool built);
  /// Solves J dq = rhs with the last factorisation into dq.
  void solveJacobian(const VecX& rhs, VecX& dq);
  /// Newton-Krylov update (NewtonOptions::krylov_iterations): update_ with J update_ = residual_,
  /// J the Jacobian evaluate() built at q, by GMRES preconditioned with the kept factorisation,
  /// refactoring at q when there is none usable or GMRES falls short. False if that fails.
  bool krylovUpdate(const RodState& start, const VecX& q, double dt, const ReferenceFrames& frames);
  /// Builds the dense Newton system at q (after evaluate() with its Jacobian) and factors it.
  bool refactorDense(const RodState& start, const VecX& q, double dt,
                     const ReferenceFrames& frames);
  EffectContext contextAt(const RodState& start, const VecX& q, double dt,
                          const ReferenceFrames& frames) const;
  void transportInto(const VecX& q, const ReferenceFrames& previous, ReferenceFrames& frames) const;

  RodNetwork net_;
  std::vector<EffectPtr> effects_;
  // The effects in each role (Effect::as), in the effects' order.
  std::vector<const ForceLaw*> forces_;
  std::vector<const ForceLaw*> dense_forces_;  ///< forces with a dense Jacobian block
  std::vector<StepHooks*> step_hooks_;
  std::vector<MappedIterates*> mapped_iterates_;  ///< followed by preimage (Newton-Krylov)
  VecX mapped_from_;  ///< the iterate before a followed update (storage reused)
  std::vector<const ViscosityLaw*> viscosity_laws_;
  std::vector<const MotorSpeedLaw*> speed_laws_;
  Medium medium_;
  NewtonOptions options_;
  /// Natural twist of the motor spring at t = 0 (the network's value, never written).
  double motor_tau_bar0_ = 0.0;
  /// What evaluate() uses for this attempt: the motor spring's natural twist, the viscosity.
  NaturalTwistOverride motor_twist_;
  double attempt_viscosity_ = 0.0;
  double attempt_dt_ = 0.0;
  double viscosity_factor_ = 1.0;  ///< of the last accepted (sub)step (reported only)
  bool any_fixed_ = false;
  SparseAssembler assembler_;
  VecX residual_, external_;
  JacobianSolver lu_;
  bool analyzed_ = false;
  // Assembly in place (docs/model.md 1.10): once the block LU has factored a Jacobian of this
  // pattern, later Jacobians are assembled straight into its storage. A refusal of the block LU
  // then needs the matrix for KLU: the Jacobian is assembled again as a matrix, and assembly in
  // place stays off for this stepper.
  bool in_place_allowed_ = true;
  bool dense_ = false;  ///< some effect has a dense Jacobian block
  DenseNewtonSystem dense_system_;
  /// Newton-Krylov (NewtonOptions::krylov_iterations): set for a plain attempt on a dense system;
  /// evaluate() then fills product_ instead of building the dense system.
  bool krylov_attempt_ = false;
  DenseJacobianProduct product_;
  Gmres gmres_;
  VecX row_scales_, scaled_rhs_, unscaled_;
  VecX preimage_;  ///< z of update_ = C z (dense systems; the last GMRES preconditioner output)
  /// The factored dense Jacobian kept for later updates and steps.
  struct KeptFactorization {
    bool valid = false;
    bool stale = false;  ///< the last GMRES solve needed many products: refactor next time
    double dt = 0.0, viscosity = 0.0;
  } kept_;
  int factorizations_ = 0;
  int analyses_ = 0;
  VecX previous_iterate_;  ///< to undo a chord update that raised the residual
  // Storage reused by every step (no allocation inside a step once the first one has run): the
  // Newton iterate and update, each subdivision depth's trial state, the effects' saved states.
  VecX iterate_, update_;
  std::deque<RodState> trial_states_;  // a deque: growing it keeps deeper levels' references
  std::vector<std::vector<double>> saved_effect_states_;
  ReferenceFrames frames_, trial_frames_;  ///< of the iterate and of a line-search trial
  /// The last accepted (sub)step's start and end rates, for the second-order predictor.
  struct PredictorHistory {
    bool valid = false;
    double time = 0.0, dt = 0.0;  ///< end time and length of that step
    VecX qdot_start, qdot_end;
  } predictor_;
  StepProfile* profile_ = nullptr;
};

}  // namespace flagella
