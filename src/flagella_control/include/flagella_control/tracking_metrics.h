// How well a run followed its path: cross-track error of the TRUE head position against the
// reference path (nearest point over the whole path), its maximum and root mean square.
#pragma once

#include <algorithm>
#include <cmath>

#include "flagella_control/path.h"

namespace flagella::control {

struct TrackingStats {
  long samples = 0;
  double max_abs = 0.0;  ///< [m]
  double sum_sq = 0.0;   ///< [m^2]

  void add(double cross_track) {
    ++samples;
    max_abs = std::max(max_abs, std::abs(cross_track));
    sum_sq += cross_track * cross_track;
  }
  /// Distance of `position` to the whole path, added as one sample.
  void add(const Path& path, const Vec2& position) { add(path.project(position).distance); }
  double rms() const { return samples > 0 ? std::sqrt(sum_sq / samples) : 0.0; }
};

}  // namespace flagella::control
