// A simulation driven from outside, as the ROS node and the LCM harness drive it: motor and
// slider commands pass through validating gates with a failsafe, solver failures are handled
// by a fixed strategy and reported, and the state is read as snapshots, IMU samples and camera
// fixes.
#pragma once

#include <memory>
#include <string>

#include "flagella_sim/actuation/command_gate.h"
#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/actuation/slider_commands.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/accelerometer.h"
#include "flagella_sim/runtime/camera_model.h"
#include "flagella_sim/runtime/imu_model.h"
#include "flagella_sim/runtime/rod_snapshot.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella {

struct SessionOptions {
  double max_motor_speed = units::rpmToRadPerSec(200.0);  ///< |omega_T| [rad/s]
  double command_timeout = 0.5;  ///< failsafe: motor stops this long after the last command [s]
  /// Before the first command: "config" follows the config's motor schedule, "stopped" holds 0.
  std::string initial_motor = "config";
  double slider_min = -0.02, slider_max = 0.02;  ///< internal-mass travel [m]
  ImuOptions imu;
  AccelerometerOptions accelerometer;
  CameraOptions camera;

  /// Throws ConfigError naming the field and its allowed range.
  void validate() const;
};

enum class HealthLevel { Ok, Warn, Error };

struct SessionHealth {
  HealthLevel level = HealthLevel::Ok;
  std::string message = "running";
  long steps = 0;
  long newton_iterations = 0;
  long subdivided_steps = 0;
  long damped_steps = 0;     ///< (sub)steps solved only by the damped (line-search) retry
  long solver_failures = 0;  ///< steps that failed even after subdivision
  long motor_accepted = 0, motor_rejected = 0;
  long slider_accepted = 0, slider_rejected = 0;
  bool failsafe_active = false;
  bool halted = false;
  double motor_applied = 0.0;  ///< omega_T used in the last step [rad/s]
  /// The slider's position [m] when the config has one (`slider:`), else the last accepted
  /// command (nothing moves).
  double slider_position = 0.0;
  bool slider_at_stop = false;  ///< resting against a hard stop of its travel
  std::string last_rejection;
  std::string last_solver_failure;
};

class SimSession {
 public:
  /// Throws ConfigError for invalid options.
  SimSession(SimulationConfig config, SessionOptions options);

  /// Offers a motor rate [rad/s] at the current simulated time.
  CommandVerdict commandMotor(double omega);
  /// Offers a slider position [m]; with a `slider:` section in the config the slider drives
  /// there (actuation/slider.h), else it is only stored and reported.
  CommandVerdict commandSlider(double position);

  /// Advances one dt. Failure strategy: a step that fails even after subdivision is retried
  /// once with the motor stopped (counted, reported as a warning); if that fails too the
  /// session halts (error) and the state stays at the last good step until reset().
  /// Returns false when halted (nothing changed).
  bool step();
  /// Rebuilds the robot at t = 0 and forgets all commands, counters and failures.
  void reset();

  double time() const { return sim_->time(); }
  double dt() const { return config_.dt; }
  bool halted() const { return halted_; }
  /// The motor command failsafe holds the motor stopped now (cheap; health() has the rest).
  bool failsafeActive() const;
  RodSnapshot snapshot() const;
  /// One IMU measurement of the current head motion (advances the noise generator).
  ImuSample measureImu();
  /// The head accelerometer's output now (a new reading at its output data rate, held in
  /// between; head frame, runtime/accelerometer.h).
  const AccelerometerReading& measureAccelerometer();
  /// One camera fix of the head centre in the output frame (advances the noise generator).
  CameraFix measureCamera();
  /// False when the camera is off (rate 0) or inside its dropout window.
  bool cameraAvailable() const { return camera_.available(time()); }
  SessionHealth health() const;
  const Simulation& simulation() const { return *sim_; }
  const SessionOptions& options() const { return options_; }
  /// Rotation from the simulation frame to the output frame (z up).
  const Eigen::Quaterniond& outputFrame() const { return output_from_sim_; }

 private:
  void start();

  SimulationConfig config_;
  SessionOptions options_;
  std::unique_ptr<Simulation> sim_;  ///< its motor takes the commands (Motor::takeCommands)
  SliderCommands slider_commands_;   ///< latched into the slider each step
  ImuModel imu_;
  Accelerometer accelerometer_;
  CameraModel camera_;
  HeadMotionTracker head_motion_;
  Eigen::Quaterniond output_from_sim_;
  bool halted_ = false;
  long steps_ = 0, solver_failures_ = 0;
  std::string last_failure_;
};

}  // namespace flagella
