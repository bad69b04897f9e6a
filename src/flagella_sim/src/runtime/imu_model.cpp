#include "flagella_sim/runtime/imu_model.h"

#include <cmath>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

namespace {
constexpr double kMaxImuRate = 1e4;   // [Hz]
constexpr double kMaxNoiseStd = 1e3;  // any unit; beyond this the sensor is meaningless
constexpr double kMaxBias = 1e3;

}  // namespace

void ImuOptions::validate() const {
  requireInRange("imu.rate", rate, 1e-3, kMaxImuRate, "Hz");
  requireInRange("imu.orientation_noise_std", orientation_noise_std, 0.0, kMaxNoiseStd, "rad");
  requireInRange("imu.gyro_noise_std", gyro_noise_std, 0.0, kMaxNoiseStd, "rad/s");
  requireInRange("imu.accel_noise_std", accel_noise_std, 0.0, kMaxNoiseStd, "m/s^2");
  for (int i = 0; i < 3; ++i) {
    requireInRange("imu.gyro_bias[" + std::to_string(i) + "]", gyro_bias[i], -kMaxBias, kMaxBias,
                   "rad/s");
    requireInRange("imu.accel_bias[" + std::to_string(i) + "]", accel_bias[i], -kMaxBias, kMaxBias,
                   "m/s^2");
  }
}

Vec3 specificForceInHead(const HeadMotion& truth, const Vec3& gravity) {
  // f = a - g: an accelerometer at rest reads +|g| along the vertical.
  return truth.orientation.toRotationMatrix().transpose() * (truth.acceleration - gravity);
}

ImuModel::ImuModel(ImuOptions options, Vec3 gravity)
    : options_(std::move(options)), gravity_(std::move(gravity)), rng_(options_.seed) {
  options_.validate();
}

Vec3 ImuModel::noise(double std_dev) {
  if (std_dev == 0.0) return Vec3::Zero();
  return std_dev * Vec3(unit_normal_(rng_), unit_normal_(rng_), unit_normal_(rng_));
}

ImuSample ImuModel::measure(const HeadMotion& truth) {
  ImuSample s;
  s.time = truth.time;
  const Eigen::Matrix3d world_from_head = truth.orientation.toRotationMatrix();
  // Orientation error as a small rotation about a random axis (head frame).
  const Vec3 tilt = noise(options_.orientation_noise_std);
  const Eigen::Quaterniond error(
      Eigen::AngleAxisd(tilt.norm(), tilt.norm() > 0.0 ? Vec3(tilt.normalized()) : Vec3::UnitZ()));
  s.orientation = (truth.orientation * error).normalized();
  s.angular_velocity = world_from_head.transpose() * truth.angular_velocity + options_.gyro_bias +
                       noise(options_.gyro_noise_std);
  s.linear_acceleration =
      specificForceInHead(truth, gravity_) + options_.accel_bias + noise(options_.accel_noise_std);
  s.orientation_variance = options_.orientation_noise_std * options_.orientation_noise_std;
  s.angular_velocity_variance = options_.gyro_noise_std * options_.gyro_noise_std;
  s.linear_acceleration_variance = options_.accel_noise_std * options_.accel_noise_std;
  return s;
}

void HeadMotionTracker::update(double time, const Eigen::Quaterniond& orientation,
                               const Vec3& velocity) {
  latest_.time = time;
  latest_.orientation = orientation;
  if (have_previous_ && time > time_) {
    const double dt = time - time_;
    // Rotation over the interval, expressed in the world frame: R_now R_prev^T.
    const Eigen::AngleAxisd turn(orientation * orientation_.inverse());
    latest_.angular_velocity = turn.axis() * (turn.angle() / dt);
    latest_.acceleration = (velocity - velocity_) / dt;
  }
  have_previous_ = true;
  time_ = time;
  orientation_ = orientation;
  velocity_ = velocity;
}

}  // namespace flagella
