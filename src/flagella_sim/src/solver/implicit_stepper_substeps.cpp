// ImplicitStepper's (sub)steps: motor load, damped retry, subdivision (docs/model.md 1.9, 1.10).
#include <cmath>
#include <sstream>

#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/solver/implicit_stepper.h"

namespace flagella {

namespace {

// A failed step names a joint folded beyond this turning angle (cos = -0.999, about 177.4 deg).
const double kFoldedJointAngle = std::acos(-0.999);

}  // namespace

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
  const SubstepDrive drive = substepDrive(state, t_next, dt, motor);
  const StepStart start{net_, state, dt, medium_, drive.viscosity};
  {
    ProfileScope timer(profile_, &StepProfile::effects);
    for (StepHooks* hooks : step_hooks_) hooks->beginStep(start);
  }
  const Attempt a =
      solveWithDampedRetry(state, trial, dt, drive.motor.twist_offset, drive.viscosity);
  if (a.converged) {
    acceptSubstep(state, trial, t_next, drive, motor);
    return {a.iterations, 1, a.residual, a.damped_retried ? 1 : 0};
  }
  if (depth >= options_.max_subdivision_depth)
    throw SolverFailure(nonConvergenceMessage(state, dt, depth, a));
  return subdivide(state, dt, motor, depth, a.iterations);
}

ImplicitStepper::SubstepDrive ImplicitStepper::substepDrive(const RodState& state, double t_next,
                                                            double dt, const Motor& motor) const {
  // Effect hooks of this (sub)step: viscosity factor (product); the motor's drive.
  SubstepDrive drive;
  for (const ViscosityLaw* law : viscosity_laws_)
    drive.viscosity_factor *= law->viscosityFactor(t_next);
  drive.viscosity = medium_.viscosity() * drive.viscosity_factor;
  drive.motor = motor.drive(net_, state, t_next, dt);
  if (!std::isfinite(drive.motor.speed)) {
    std::ostringstream msg;
    msg << "motor " << (std::isfinite(drive.motor.command) ? "speed" : "command")
        << " is not finite (" << drive.motor.speed << ") at t = " << t_next << " s";
    throw SolverFailure(msg.str());
  }
  return drive;
}

ImplicitStepper::Attempt ImplicitStepper::solveWithDampedRetry(const RodState& start,
                                                               RodState& result, double dt,
                                                               double motor_offset,
                                                               double viscosity) {
  Attempt a = solveStep(start, result, dt, motor_offset, viscosity, false);
  if (!a.converged && options_.damped_retry) {
    const Attempt plain = a;
    a = solveStep(start, result, dt, motor_offset, viscosity, true);
    a.iterations += plain.iterations;
    a.damped_retried = true;
  }
  return a;
}

void ImplicitStepper::acceptSubstep(RodState& state, RodState& trial, double t_next,
                                    const SubstepDrive& drive, Motor& motor) {
  trial.time = t_next;
  motor.apply(drive.motor, trial);
  {
    ProfileScope timer(profile_, &StepProfile::effects);
    for (StepHooks* hooks : step_hooks_) hooks->acceptStep(net_, state, trial);
  }
  viscosity_factor_ = drive.viscosity_factor;
  std::swap(state, trial);  // trial keeps the old state's storage for the next step
}

StepReport ImplicitStepper::subdivide(RodState& state, double dt, Motor& motor, int depth,
                                      int failed_iterations) {
  RodState half = state;
  StepReport first = stepRecursive(half, 0.5 * dt, motor, depth + 1);
  StepReport second = stepRecursive(half, 0.5 * dt, motor, depth + 1);
  state = std::move(half);
  return {failed_iterations + first.newton_iterations + second.newton_iterations,
          first.substeps + second.substeps, second.residual,
          first.damped_retries + second.damped_retries};
}

std::string ImplicitStepper::nonConvergenceMessage(const RodState& state, double dt, int depth,
                                                   const Attempt& attempt) const {
  std::ostringstream msg;
  msg << "Newton did not converge at t = " << state.time << " s with dt = " << dt << " s after "
      << depth << " subdivisions (scaled residual " << attempt.residual << ", tolerance "
      << options_.residual_tolerance << "; the last attempt ended on " << attempt.failure << ")"
      << foldedJointNote(state);
  return msg.str();
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
  effect_states.resize(step_hooks_.size());
  for (size_t i = 0; i < step_hooks_.size(); ++i)
    effect_states[i] = step_hooks_[i]->internalState();
  const double viscosity_factor = viscosity_factor_;
  const Motor::Record motor_record = motor.record();
  auto restore = [&] {
    for (size_t i = 0; i < step_hooks_.size(); ++i)
      step_hooks_[i]->setInternalState(effect_states[i]);
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

}  // namespace flagella
