#include "node_params.h"

#include <cmath>
#include <sstream>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"

namespace flagella::sim_node {

namespace {
constexpr double kMaxMotorRpm = 1e5;
constexpr double kMaxTimeout = 1e6;  // [s]
constexpr double kMaxNoise = 1e3;
constexpr double kMaxImuRate = 1e4;               // [Hz]
constexpr double kMaxSliderTravel = 1.0;          // [m]
constexpr double kMaxCameraRate = 1e3;            // [Hz]
constexpr double kMaxTime = 1e9;                  // [s]
constexpr double kMaxAccelerometerNoise = 10.0;   // [m/s^2], as AccelerometerOptions::validate
constexpr double kMaxAccelerometerRate = 3200.0;  // [Hz], the ADXL345's fastest output rate
}  // namespace

double rangedParam(const ros::NodeHandle& nh, const std::string& name, double fallback, double min,
                   double max, const std::string& unit) {
  double value = fallback;
  if (nh.hasParam(name) && !nh.getParam(name, value)) {
    // Present but not a number (a string, a list...).
    throw flagella::ConfigError("parameter ~" + name + " must be a number in [" +
                                std::to_string(min) + ", " + std::to_string(max) + "] " + unit);
  }
  flagella::requireInRange("parameter ~" + name, value, min, max, unit);
  return value;
}

flagella::Vec3 vectorParam(const ros::NodeHandle& nh, const std::string& name,
                           const flagella::Vec3& fallback) {
  std::vector<double> values;
  if (!nh.hasParam(name)) return fallback;
  if (!nh.getParam(name, values) || values.size() != 3)
    throw flagella::ConfigError("parameter ~" + name + " must be a list of 3 numbers");
  for (double v : values)
    if (!std::isfinite(v))
      throw flagella::ConfigError("parameter ~" + name + " must contain finite numbers");
  return flagella::Vec3(values[0], values[1], values[2]);
}

std::vector<std::string> splitOverrides(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  std::string item;
  while (in >> item) out.push_back(item);
  return out;
}

flagella::SessionOptions sessionOptionsFromParams(const ros::NodeHandle& nh) {
  flagella::SessionOptions o;
  o.max_motor_speed = flagella::units::rpmToRadPerSec(
      rangedParam(nh, "max_motor_rpm", flagella::units::radPerSecToRpm(o.max_motor_speed), 1e-6,
                  kMaxMotorRpm, "rpm"));
  o.command_timeout = rangedParam(nh, "command_timeout", o.command_timeout, 0.0, kMaxTimeout,
                                  "s of simulated time (0: no failsafe)");
  nh.param<std::string>("initial_motor", o.initial_motor, o.initial_motor);
  o.slider_min =
      rangedParam(nh, "slider_min", o.slider_min, -kMaxSliderTravel, kMaxSliderTravel, "m");
  o.slider_max = rangedParam(nh, "slider_max", o.slider_max, o.slider_min, kMaxSliderTravel, "m");
  o.imu.rate = rangedParam(nh, "imu_rate", o.imu.rate, 1e-3, kMaxImuRate, "Hz");
  o.imu.orientation_noise_std =
      rangedParam(nh, "imu_orientation_noise", o.imu.orientation_noise_std, 0.0, kMaxNoise, "rad");
  o.imu.gyro_noise_std =
      rangedParam(nh, "imu_gyro_noise", o.imu.gyro_noise_std, 0.0, kMaxNoise, "rad/s");
  o.imu.accel_noise_std =
      rangedParam(nh, "imu_accel_noise", o.imu.accel_noise_std, 0.0, kMaxNoise, "m/s^2");
  o.imu.gyro_bias = vectorParam(nh, "imu_gyro_bias", o.imu.gyro_bias);
  o.imu.accel_bias = vectorParam(nh, "imu_accel_bias", o.imu.accel_bias);
  int seed = static_cast<int>(o.imu.seed);
  nh.param("imu_seed", seed, seed);
  o.imu.seed = static_cast<unsigned>(seed);
  o.camera.rate = rangedParam(nh, "camera_rate", o.camera.rate, 0.0, kMaxCameraRate, "Hz (0: off)");
  o.camera.noise_std = rangedParam(nh, "camera_noise", o.camera.noise_std, 0.0, kMaxNoise, "m");
  o.camera.dropout_start = rangedParam(nh, "camera_dropout_start", o.camera.dropout_start,
                                       -kMaxTime, kMaxTime, "s of simulated time (negative: none)");
  if (o.camera.dropout_start >= 0.0)
    o.camera.dropout_end =
        rangedParam(nh, "camera_dropout_end", o.camera.dropout_end, o.camera.dropout_start,
                    kMaxTime, "s of simulated time (at or after ~camera_dropout_start)");
  else
    o.camera.dropout_end =
        rangedParam(nh, "camera_dropout_end", o.camera.dropout_end, -kMaxTime, 0.0,
                    "s (no window while ~camera_dropout_start is negative)");
  seed = static_cast<int>(o.camera.seed);
  nh.param("camera_seed", seed, seed);
  o.camera.seed = static_cast<unsigned>(seed);
  // A second camera through the tank's side: the fix carries the height z.
  nh.param("camera_stereo", o.camera.stereo, o.camera.stereo);
  o.camera.height_noise_std =
      rangedParam(nh, "camera_height_noise", o.camera.height_noise_std, 0.0, kMaxNoise, "m");
  // The head accelerometer (ADXL345-like) as the IMU message's linear acceleration.
  nh.param("accelerometer_feeds_imu", o.accelerometer.feeds_imu, o.accelerometer.feeds_imu);
  o.accelerometer.range_g = rangedParam(nh, "accelerometer_range_g", o.accelerometer.range_g, 2.0,
                                        16.0, "g (2, 4, 8 or 16)");
  o.accelerometer.noise_std = rangedParam(nh, "accelerometer_noise", o.accelerometer.noise_std, 0.0,
                                          kMaxAccelerometerNoise, "m/s^2");
  o.accelerometer.output_rate = rangedParam(nh, "accelerometer_rate", o.accelerometer.output_rate,
                                            0.1, kMaxAccelerometerRate, "Hz");
  seed = static_cast<int>(o.accelerometer.seed);
  nh.param("accelerometer_seed", seed, seed);
  o.accelerometer.seed = static_cast<unsigned>(seed);
  o.validate();
  return o;
}

}  // namespace flagella::sim_node
