// Where the time of implicit steps goes: wall time per part, summed over the steps taken while
// profiling is on (ImplicitStepper::setProfile). Filled by the stepper; read by benchmarks.
#pragma once

#include <chrono>

namespace flagella {

struct StepProfile {
  // Wall time [s] of each part.
  double frames = 0.0;         ///< reference-frame transport (docs/model.md 1.3)
  double elastic = 0.0;        ///< inertia, stretching and bend-twist gradients and Hessians
  double effects = 0.0;        ///< external effects' forces and Jacobians, step hooks
  double assembly = 0.0;       ///< sparse bookkeeping: pass start/finish, pinned DOFs, dense build
  double factorization = 0.0;  ///< LU (symbolic analysis included when it happens)
  double solve = 0.0;          ///< triangular solves
  double convergence = 0.0;    ///< residual norms, update norms, finiteness checks
  double total = 0.0;          ///< whole steps (the rest: state copies, motor, bookkeeping)
  // The same time cut another way (overlapping the parts above): whole evaluations of the Newton
  // residual, without and with its Jacobian (frames transport excluded).
  double residual_evaluations = 0.0;
  double jacobian_evaluations = 0.0;
  // Counts.
  long steps = 0;
  long updates = 0;    ///< Newton updates (solves)
  long residuals = 0;  ///< residual evaluations (with or without Jacobian)
  long jacobians = 0;  ///< Jacobian evaluations
  long factorizations = 0;
  long krylov_iterations = 0;  ///< GMRES products (solver.krylov_iterations)

  double other() const {
    return total - frames - elastic - effects - assembly - factorization - solve - convergence;
  }
};

/// Adds the wall time of its scope to one part of a profile; does nothing for a null profile.
class ProfileScope {
 public:
  ProfileScope(StepProfile* profile, double StepProfile::*part) : profile_(profile), part_(part) {
    if (profile_) start_ = std::chrono::steady_clock::now();
  }
  ~ProfileScope() {
    if (profile_)
      profile_->*part_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ProfileScope(const ProfileScope&) = delete;
  ProfileScope& operator=(const ProfileScope&) = delete;

 private:
  StepProfile* profile_;
  double StepProfile::*part_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace flagella
