#include "flagella_sim/runtime/camera_model.h"

#include <cmath>

#include "flagella_sim/core/parameter_set.h"

namespace flagella {

namespace {
constexpr double kMaxCameraRate = 1e3;  // [Hz]
constexpr double kMaxNoiseStd = 1e3;    // [m]; beyond this the fix is meaningless
constexpr double kMaxTime = 1e9;        // [s]
constexpr double kTimeSlack = 1e-9;     // [s]: round-off of simulated time summed over steps
}  // namespace

void CameraOptions::validate() const {
  requireInRange("camera.rate", rate, 0.0, kMaxCameraRate, "Hz (0: off)");
  requireInRange("camera.noise_std", noise_std, 0.0, kMaxNoiseStd, "m");
  requireInRange("camera.height_noise_std", height_noise_std, 0.0, kMaxNoiseStd, "m");
  requireInRange("camera.dropout_start", dropout_start, -kMaxTime, kMaxTime, "s (negative: none)");
  if (dropout_start >= 0.0) {
    requireInRange("camera.dropout_end", dropout_end, dropout_start, kMaxTime,
                   "s (at or after camera.dropout_start)");
  } else {
    requireInRange("camera.dropout_end", dropout_end, -kMaxTime, 0.0,
                   "s (no window while camera.dropout_start is negative)");
  }
}

bool CameraOptions::inDropout(double time) const {
  return dropout_start >= 0.0 && time > dropout_start - kTimeSlack &&
         time < dropout_end - kTimeSlack;
}

CameraModel::CameraModel(CameraOptions options)
    : options_(std::move(options)), rng_(options_.seed) {
  options_.validate();
}

CameraFix CameraModel::measure(double time, const Vec3& head_position) {
  CameraFix fix;
  fix.time = time;
  fix.position = head_position.head<2>();
  if (options_.noise_std > 0.0)
    fix.position += options_.noise_std * Eigen::Vector2d(unit_normal_(rng_), unit_normal_(rng_));
  fix.variance = options_.noise_std * options_.noise_std;
  if (options_.stereo) {
    fix.has_height = true;
    fix.height = head_position.z();
    if (options_.height_noise_std > 0.0)
      fix.height += options_.height_noise_std * unit_normal_(rng_);
    fix.height_variance = options_.height_noise_std * options_.height_noise_std;
  }
  return fix;
}

}  // namespace flagella
