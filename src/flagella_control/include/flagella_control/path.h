// A prescribed 2-D path in the horizontal plane (output frame, z up): a chain of straight lines
// and circular arcs, with arclength s, nearest-point projection and signed cross-track error.
// Built from a shape description (polyline, circle, rectangle, triangle) or a list of points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "flagella_control/heading.h"

namespace flagella::control {

using Vec2 = Eigen::Vector2d;

/// Unit vector at azimuth `angle` [rad].
inline Vec2 unitVector(double angle) { return Vec2(std::cos(angle), std::sin(angle)); }
/// z component of the 2-D cross product: > 0 when b is counter-clockwise from a.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

struct PathElement {
  enum class Kind { Line, Arc } kind = Kind::Line;
  Vec2 start = Vec2::Zero();
  Vec2 end = Vec2::Zero();     ///< Line only (Arc: derived)
  Vec2 center = Vec2::Zero();  ///< Arc only
  double radius = 0.0;         ///< Arc only [m]
  double start_angle = 0.0;    ///< Arc only: polar angle of `start` about `center` [rad]
  double sweep = 0.0;          ///< Arc only: signed swept angle, CCW positive [rad]
  double length = 0.0;         ///< [m]
  double s_start = 0.0;        ///< arclength at the element's start [m]
};

/// A point on the path.
struct PathPoint {
  Vec2 position = Vec2::Zero();
  double tangent = 0.0;    ///< direction of travel, azimuth [rad]
  double curvature = 0.0;  ///< signed, CCW (left) turn positive [1/m]
  int element = 0;
};

/// Nearest point of the path to a query point.
struct PathProjection {
  PathPoint point;
  double s = 0.0;            ///< arclength of the nearest point (lap-cumulative if searched so)
  double cross_track = 0.0;  ///< signed distance, query left of the direction of travel > 0 [m]
  double distance = 0.0;     ///< |cross_track| or distance to an end point [m]
};

class Path {
 public:
  Path() = default;
  /// Throws std::invalid_argument for fewer than 2 points, non-finite or repeated points.
  static Path polyline(const std::vector<Vec2>& points, bool closed);
  /// Full circle through `start`, starting in direction `start_tangent`; ccw or clockwise.
  static Path circle(const Vec2& start, double start_tangent, double radius, bool ccw);

  void appendLine(const Vec2& start, const Vec2& end);
  void appendArc(const Vec2& center, double radius, double start_angle, double sweep);

  double length() const { return length_; }
  bool closed() const { return closed_; }
  bool empty() const { return elements_.empty(); }
  const std::vector<PathElement>& elements() const { return elements_; }

  /// The point at arclength s. Closed paths wrap (s modulo length); open paths clamp to the ends.
  PathPoint at(double s) const;
  /// Nearest point with arclength in [s_min, s_max] (lap-cumulative values allowed on a closed
  /// path; on an open path the range is clipped to [0, length]). Allocation-free.
  PathProjection project(const Vec2& query, double s_min, double s_max) const;
  /// Nearest point over the whole path (one lap).
  PathProjection project(const Vec2& query) const { return project(query, 0.0, length_); }

  /// This path moved rigidly: rotated by `yaw` about the origin, then shifted by `offset`.
  Path transformed(const Vec2& offset, double yaw) const;
  /// Points every `spacing` metres (and every corner), for display and plots.
  std::vector<Vec2> sample(double spacing) const;
  /// Signed heading change at the junction after element i (to element i+1, wrapping on a
  /// closed path; 0 after the last element of an open path) [rad], in (-pi, pi].
  double turnAfter(int i) const;

 private:
  void setClosed(bool closed) { closed_ = closed; }
  PathProjection projectOnElement(const PathElement& e, const Vec2& q, double s_lo,
                                  double s_hi) const;

  std::vector<PathElement> elements_;
  double length_ = 0.0;
  bool closed_ = false;
};

}  // namespace flagella::control
