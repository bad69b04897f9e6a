#include "flagella_sim/solver/chord_predictor.h"

#include <cmath>

namespace flagella {

Vec3 rotatingChordPrediction(const Vec3& v_prev, const Vec3& v_last) {
  const Vec3 linear = 2.0 * v_last - v_prev;
  const double n_prev = v_prev.norm(), n_last = v_last.norm();
  if (!(n_prev > 0.0) || !(n_last > 0.0)) return linear;
  const Vec3 axis = v_prev.cross(v_last) / (n_prev * n_last);  // sin(angle) times the unit axis
  const double cos_angle = v_prev.dot(v_last) / (n_prev * n_last), sin_angle = axis.norm();
  if (cos_angle < 0.5) return linear;
  Vec3 turned = v_last;
  if (sin_angle > 0.0) {
    // Rodrigues' rotation of v_last about the unit axis k by the same angle
    const Vec3 k = axis / sin_angle;
    turned =
        v_last * cos_angle + k.cross(v_last) * sin_angle + k * (k.dot(v_last) * (1.0 - cos_angle));
  }
  return turned * (n_last / n_prev);
}

}  // namespace flagella
