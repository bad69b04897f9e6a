// A configured run: robot + medium + effects + motor + stepper, with sampled outputs.
// The one object the CLI, the benchmarks, the ROS node and the identification tool drive.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor.h"
#include "flagella_sim/actuation/slider.h"
#include "flagella_sim/outputs/trajectory.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "flagella_sim/solver/implicit_stepper.h"

namespace flagella {

class Simulation {
 public:
  explicit Simulation(const SimulationConfig& config);

  /// Replaces the motor's schedule (controllers plug in here).
  void setMotor(std::shared_ptr<const MotorCommand> schedule) {
    motor_.setSchedule(std::move(schedule));
  }
  /// The motor: commands in, natural-twist rate out (actuation/motor.h).
  Motor& motor() { return motor_; }
  const Motor& motor() const { return motor_; }
  /// The mass-transformer's slider (config section `slider:`), or nullptr. Each step moves it
  /// toward its target and sets effects.com_offset.offset = l_0 + (m_s / m_h) x_s, l_0 being the
  /// configured offset (docs/model.md 5).
  Slider* slider() { return slider_ ? &*slider_ : nullptr; }
  const Slider* slider() const { return slider_ ? &*slider_ : nullptr; }

  /// One step of config().dt. Throws SolverFailure (state unchanged) if Newton cannot recover.
  StepReport step();
  /// Runs until `duration` more seconds have elapsed, sampling every output_interval.
  /// `progress(fraction)` is called after every sample if given.
  void run(double duration, const std::function<void(double)>& progress = {});

  /// Appends a sample of the current state to the trajectory.
  void recordSample();
  /// Appends a sample unless the last one is already at the current time (end of a run).
  void recordFinalSample();
  TrajectorySample sample() const;
  const std::vector<TrajectorySample>& trajectory() const { return trajectory_; }
  SummaryMetrics summary() const;
  void setRecordNodes(bool on) { record_nodes_ = on; }

  /// Named parameters: "medium.viscosity", "effects.stokes_head.C_t", ...
  double parameter(const std::string& name) const;
  void setParameter(const std::string& name, double value);
  std::vector<std::string> parameterNames() const;
  /// Value, range, unit and description of a named parameter.
  const ParameterSpec& parameterSpec(const std::string& name) const;

  const RodState& state() const { return state_; }
  const SimulationConfig& config() const { return config_; }
  const ImplicitStepper& stepper() const { return stepper_; }
  /// Times the parts of every later step into `profile` (not owned; null stops it).
  void setProfile(StepProfile* profile) { stepper_.setProfile(profile); }
  const RodNetwork& network() const { return stepper_.network(); }
  double time() const { return state_.time; }
  /// Motor command of the last step [rad/s].
  double lastMotorCommand() const { return motor_.lastCommand(); }
  /// Motor speed applied in the last step (the command unless an effect such as dc_motor
  /// modifies it) [rad/s].
  double lastMotorSpeed() const { return motor_.lastSpeed(); }
  /// Viscosity of the last step [Pa s] (medium.viscosity times any drift).
  double currentViscosity() const { return stepper_.currentViscosity(); }

 private:
  ParameterSet& parameterOwner(const std::string& name, std::string& local) const;
  /// Sets the couple's offset from the slider's position.
  void applySliderOffset();

  SimulationConfig config_;
  ImplicitStepper stepper_;
  Motor motor_;
  std::optional<Slider> slider_;
  Effect* slider_couple_ = nullptr;  ///< the com_offset effect the slider drives
  double neutral_offset_ = 0.0;      ///< l_0 [m]: the configured effects.com_offset.offset
  RodState state_;
  std::vector<TrajectorySample> trajectory_;
  bool record_nodes_ = false;
  double next_sample_time_ = 0.0;
  long newton_iterations_ = 0;
  long subdivided_steps_ = 0;
  long damped_steps_ = 0;
};

/// The configured robot: robot.type multi_tail (docs/model.md 8.1-8.3) or helical (8.4).
RodNetwork buildRobot(const SimulationConfig& config);

/// The motor command a MotorSpec describes.
std::shared_ptr<const MotorCommand> makeMotor(const MotorSpec& spec);

}  // namespace flagella
