// The firmware-style controller contract: a fixed-step function from sensor inputs to actuator
// outputs, ROS-free, LCM-free and allocation-free in step(). The ROS controller node and the
// LCM harness are two thin shells around the same object.
#pragma once

#include <cstdint>

namespace flagella::control {

struct ControllerInputs {
  double time = 0.0;  ///< [s] of the robot's clock
  // IMU (head frame, REP-145)
  bool imu_valid = false;
  double orientation[4] = {0.0, 0.0, 0.0, 1.0};  ///< quaternion x, y, z, w, head in world
  double angular_velocity[3] = {0.0, 0.0, 0.0};  ///< [rad/s], head frame
  /// Specific force [m/s^2], head frame (the head accelerometer; at rest +g upward).
  double linear_acceleration[3] = {0.0, 0.0, 0.0};
  // Optional position fix (an overhead camera: x, y; two cameras on the tank: x, y, z)
  bool position_valid = false;
  double position[3] = {0.0, 0.0, 0.0};  ///< [m], world x, y, z (z up)
};

enum class ControllerMode : std::uint8_t { Idle = 0, Running = 1, Finished = 2, Fault = 3 };

struct ControllerOutputs {
  double motor_command = 0.0;  ///< signed motor rate [rad/s]
  bool slider_valid = false;
  double slider_position = 0.0;  ///< [m]
  ControllerMode mode = ControllerMode::Idle;
};

class ControllerCore {
 public:
  virtual ~ControllerCore() = default;
  /// One fixed step. Must not allocate.
  virtual ControllerOutputs step(const ControllerInputs& inputs) = 0;
  virtual void reset() = 0;
  virtual const char* name() const = 0;
};

/// Open-loop binary switching (docs/model.md 7.3): +omega for `positive_duration`, then -omega for
/// `negative_duration`, repeating from the first step. Equal halves advance along a line;
/// unequal halves steer a large circle.
class PeriodicSwitchController : public ControllerCore {
 public:
  /// Throws std::invalid_argument for a non-positive rate or duration.
  PeriodicSwitchController(double omega, double positive_duration, double negative_duration);
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override { started_ = false; }
  const char* name() const override { return "periodic_switch"; }

 private:
  double omega_, positive_, negative_;
  bool started_ = false;
  double start_time_ = 0.0;
};

}  // namespace flagella::control
