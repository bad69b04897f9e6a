#include "node_params.h"

#include <cmath>
#include <sstream>

#include "flagella_sim/core/file_paths.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "sim_node.h"

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
constexpr double kMaxRate = 1e4;                  // [Hz]
constexpr double kMaxRealTimeFactor = 1e6;
constexpr double kMaxDuration = 1e9;         // [s]
constexpr double kMaxLockstepTimeout = 1e6;  // [s wall]

std::string defaultPrefix(const ros::NodeHandle& nh) {
  std::string ns = nh.getNamespace();
  while (!ns.empty() && ns.front() == '/') ns.erase(ns.begin());
  for (char& c : ns)
    if (c == '/') c = '_';
  return ns.empty() ? "flagella" : ns;
}
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

SimNodeOptions nodeOptionsFromParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  SimNodeOptions o;
  if (!pnh.getParam("config", o.config_path) || o.config_path.empty())
    throw flagella::ConfigError("parameter ~config (path of a robot config YAML) is required");
  // a relative path: from the directory roslaunch was started in (the launch files' base_directory)
  o.config_path =
      flagella::resolveAgainst(o.config_path, pnh.param<std::string>("base_directory", ""));
  pnh.param<std::string>("world_frame", o.world_frame, o.world_frame);
  pnh.param<std::string>("tf_prefix", o.tf_prefix, defaultPrefix(nh));
  o.real_time_factor = rangedParam(pnh, "real_time_factor", o.real_time_factor, 0.0,
                                   kMaxRealTimeFactor, "(0: as fast as possible)");
  pnh.param("publish_clock", o.publish_clock, o.publish_clock);
  o.state_rate = rangedParam(pnh, "state_rate", o.state_rate, 1e-3, kMaxRate, "Hz");
  o.marker_rate = rangedParam(pnh, "marker_rate", o.marker_rate, 1e-3, kMaxRate, "Hz");
  o.path_rate = rangedParam(pnh, "path_rate", o.path_rate, 1e-3, kMaxRate, "Hz");
  o.diagnostics_rate =
      rangedParam(pnh, "diagnostics_rate", o.diagnostics_rate, 1e-3, kMaxRate, "Hz");
  o.path_max_poses =
      static_cast<int>(rangedParam(pnh, "path_max_poses", o.path_max_poses, 1, 1e7, "poses"));
  o.duration = rangedParam(pnh, "duration", o.duration, 0.0, kMaxDuration, "s (0: forever)");
  pnh.param("wait_for_subscribers", o.wait_for_subscribers, o.wait_for_subscribers);
  pnh.param<std::string>("wait_for_recorder", o.wait_for_recorder, o.wait_for_recorder);
  std::string followers;
  pnh.param<std::string>("followers", followers, "");
  std::istringstream names(followers);
  for (std::string name; names >> name;) o.followers.push_back(name);
  o.wait_timeout = rangedParam(pnh, "wait_timeout", o.wait_timeout, 0.0, 1e6, "s");
  o.progress_period =
      rangedParam(pnh, "progress_period", o.progress_period, 0.0, 1e6, "wall s (0: none)");
  pnh.param("lockstep", o.lockstep, o.lockstep);
  pnh.param("lockstep_slider", o.lockstep_slider, o.lockstep_slider);
  o.lockstep_timeout = rangedParam(pnh, "lockstep_timeout", o.lockstep_timeout, 1e-3,
                                   kMaxLockstepTimeout, "s of wall time");
  o.markers.tail_width =
      rangedParam(pnh, "marker_tail_width", o.markers.tail_width, 1e-5, 1.0, "m");
  o.markers.head_width =
      rangedParam(pnh, "marker_head_width", o.markers.head_width, 1e-5, 1.0, "m");
  return o;
}

}  // namespace flagella::sim_node
