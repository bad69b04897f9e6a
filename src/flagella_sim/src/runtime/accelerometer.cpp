#include "flagella_sim/runtime/accelerometer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/text_lists.h"

namespace flagella {

namespace {
constexpr double kMaxRate = 3200.0;           // [Hz], the ADXL345's fastest output data rate
constexpr double kMaxBias = 10.0;             // [m/s^2]
}  // namespace

void AccelerometerOptions::validate() const {
  if (!(range_g == 2.0 || range_g == 4.0 || range_g == 8.0 || range_g == 16.0))
    throw ConfigError("accelerometer.range_g must be 2, 4, 8 or 16 g, got " +
                      formatNumber(range_g));
  requireInRange("accelerometer.resolution", resolution, 1e-6, 1.0, "m/s^2");
  requireInRange("accelerometer.noise_std", noise_std, 0.0, 10.0, "m/s^2");
  for (int i = 0; i < 3; ++i)
    requireInRange("accelerometer.bias[" + std::to_string(i) + "]", bias[i], -kMaxBias, kMaxBias,
                   "m/s^2");
  requireInRange("accelerometer.output_rate", output_rate, 0.1, kMaxRate, "Hz");
}

Accelerometer::Accelerometer(AccelerometerOptions options)
    : options_(std::move(options)), rng_(options_.seed) {
  options_.validate();
}

bool Accelerometer::update(double time, const Vec3& specific_force) {
  // Output instants t_0 + n / rate, counted from the first sample (no accumulated round-off).
  const double period = 1.0 / options_.output_rate;
  const double due = sampled_ ? std::floor((time - first_time_) / period + 1e-6) : 0.0;
  if (sampled_ && due <= index_) return false;
  if (!sampled_) first_time_ = time;
  index_ = due;
  reading_.time = first_time_ + index_ * period;
  const int full_scale = static_cast<int>(
      std::floor(options_.range_g * units::kStandardGravity / options_.resolution));
  reading_.saturated = false;
  for (int a = 0; a < 3; ++a) {
    const double value = specific_force[a] + options_.bias[a] +
                         (options_.noise_std > 0.0 ? options_.noise_std * unit_normal_(rng_) : 0.0);
    const double count = std::round(value / options_.resolution);
    const double clipped =
        std::clamp(count, -static_cast<double>(full_scale), static_cast<double>(full_scale));
    reading_.saturated = reading_.saturated || clipped != count;
    reading_.counts[a] = static_cast<int>(clipped);
    reading_.acceleration[a] = clipped * options_.resolution;
  }
  sampled_ = true;
  return true;
}

double headElevationFromAcceleration(const Vec3& acceleration) {
  const double norm = acceleration.norm();
  if (!(norm > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::asin(std::clamp(acceleration.z() / norm, -1.0, 1.0));
}

}  // namespace flagella
