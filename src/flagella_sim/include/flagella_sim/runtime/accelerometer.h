// A 3-axis MEMS accelerometer on the head in the spirit of the ADXL345 the mass-transformer uses
// for head tilt (docs/model.md 7.4): selectable range (+-2/4/8/16 g), full-resolution output of
// 3.9 mg per count, white noise, constant zero-g bias, a fixed output data rate (a new reading
// every 1/rate s, held in between), saturation at the range. Axes are the head frame (m1^0, m2^0,
// t^0).
#pragma once

#include <Eigen/Core>
#include <random>

#include "flagella_sim/core/types.h"
#include "flagella_sim/core/units.h"

namespace flagella {

struct AccelerometerOptions {
  double range_g = 2.0;                  ///< full scale [g]: 2, 4, 8 or 16
  double resolution =
      3.9e-3 * units::kStandardGravity;  ///< one count [m/s^2] (full-resolution mode, 3.9 mg)
  double noise_std =
      4.3e-3 * units::kStandardGravity;  ///< per axis [m/s^2] (about 1.1 counts rms at 100 Hz)
  Vec3 bias = Vec3::Zero();              ///< zero-g offset per axis [m/s^2]
  double output_rate = 100.0;            ///< output data rate [Hz]
  unsigned seed = 1;
  /// The IMU message's linear acceleration is this accelerometer's output (counts x resolution,
  /// held between readings) instead of the IMU's own specific-force model.
  bool feeds_imu = false;

  /// Throws ConfigError naming the field and its allowed range.
  void validate() const;
};

struct AccelerometerReading {
  double time = 0.0;                                 ///< when it was sampled [s]
  Eigen::Vector3i counts = Eigen::Vector3i::Zero();  ///< raw output
  Vec3 acceleration = Vec3::Zero();                  ///< counts x resolution [m/s^2]
  bool saturated = false;                            ///< some axis at full scale
};

class Accelerometer {
 public:
  explicit Accelerometer(AccelerometerOptions options);
  /// Offers the true specific force (head frame, m/s^2) at `time`; samples it if a new output
  /// is due (the first call always samples) and returns true then. Allocation-free.
  bool update(double time, const Vec3& specific_force);
  /// The last output (held between samples).
  const AccelerometerReading& reading() const { return reading_; }
  const AccelerometerOptions& options() const { return options_; }

 private:
  AccelerometerOptions options_;
  std::mt19937 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  AccelerometerReading reading_;
  bool sampled_ = false;
  double first_time_ = 0.0;  ///< of the first sample [s]
  double index_ = 0.0;       ///< of the last output since the first
};

/// Elevation of the head axis t^0 above the horizontal from a gravity-dominated reading [rad]:
/// asin(a_z / |a|) (an accelerometer at rest reads +g upward). NaN for a zero reading.
double headElevationFromAcceleration(const Vec3& acceleration);

}  // namespace flagella
