#include "flagella_control/path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace flagella::control {
namespace {

constexpr double kMinElementLength = 1e-9;  // [m]; shorter elements are dropped

}  // namespace

Path Path::polyline(const std::vector<Vec2>& points, bool closed) {
  if (points.size() < 2)
    throw std::invalid_argument("path: a polyline needs at least 2 points, got " +
                                std::to_string(points.size()));
  Path path;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw std::invalid_argument("path: point " + std::to_string(i) + " is not finite");
    if (i > 0 && (points[i] - points[i - 1]).norm() < kMinElementLength)
      throw std::invalid_argument("path: points " + std::to_string(i - 1) + " and " +
                                  std::to_string(i) + " coincide");
  }
  for (size_t i = 0; i + 1 < points.size(); ++i) path.appendLine(points[i], points[i + 1]);
  if (closed && (points.back() - points.front()).norm() >= kMinElementLength)
    path.appendLine(points.back(), points.front());
  path.setClosed(closed);
  return path;
}

Path Path::circle(const Vec2& start, double start_tangent, double radius, bool ccw) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument("path: circle radius must be > 0, got " + std::to_string(radius));
  const double side = ccw ? 1.0 : -1.0;  // centre to the left for a CCW circle
  const Vec2 center = start + side * radius * unitVector(start_tangent + M_PI / 2.0);
  const double start_angle = std::atan2(start.y() - center.y(), start.x() - center.x());
  Path path;
  path.appendArc(center, radius, start_angle, side * 2.0 * M_PI);
  path.setClosed(true);
  return path;
}

void Path::appendLine(const Vec2& start, const Vec2& end) {
  PathElement e;
  e.kind = PathElement::Kind::Line;
  e.start = start;
  e.end = end;
  e.length = (end - start).norm();
  if (e.length < kMinElementLength) return;
  e.s_start = length_;
  length_ += e.length;
  elements_.push_back(e);
}

void Path::appendArc(const Vec2& center, double radius, double start_angle, double sweep) {
  PathElement e;
  e.kind = PathElement::Kind::Arc;
  e.center = center;
  e.radius = radius;
  e.start_angle = start_angle;
  e.sweep = sweep;
  e.start = center + radius * unitVector(start_angle);
  e.end = center + radius * unitVector(start_angle + sweep);
  e.length = radius * std::abs(sweep);
  if (e.length < kMinElementLength) return;
  e.s_start = length_;
  length_ += e.length;
  elements_.push_back(e);
}

namespace {

PathPoint pointOn(const PathElement& e, double local_s, int index) {
  PathPoint p;
  p.element = index;
  local_s = std::clamp(local_s, 0.0, e.length);
  if (e.kind == PathElement::Kind::Line) {
    const Vec2 dir = (e.end - e.start) / e.length;
    p.position = e.start + local_s * dir;
    p.tangent = std::atan2(dir.y(), dir.x());
    p.curvature = 0.0;
  } else {
    const double side = e.sweep >= 0.0 ? 1.0 : -1.0;
    const double angle = e.start_angle + side * local_s / e.radius;
    p.position = e.center + e.radius * unitVector(angle);
    p.tangent = wrapAngle(angle + side * M_PI / 2.0);
    p.curvature = side / e.radius;
  }
  return p;
}

}  // namespace

PathPoint Path::at(double s) const {
  if (elements_.empty()) return PathPoint{};
  if (closed_ && length_ > 0.0) {
    s = std::fmod(s, length_);
    if (s < 0.0) s += length_;
  } else {
    s = std::clamp(s, 0.0, length_);
  }
  // Binary search for the element containing s.
  int lo = 0, hi = static_cast<int>(elements_.size()) - 1;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (elements_[mid].s_start <= s)
      lo = mid;
    else
      hi = mid - 1;
  }
  return pointOn(elements_[lo], s - elements_[lo].s_start, lo);
}

PathProjection Path::projectOnElement(const PathElement& e, const Vec2& q, double s_lo,
                                      double s_hi) const {
  // Nearest point of the element restricted to local arclength [s_lo, s_hi].
  double local = 0.0;
  if (e.kind == PathElement::Kind::Line) {
    const Vec2 dir = (e.end - e.start) / e.length;
    local = (q - e.start).dot(dir);
  } else {
    const double side = e.sweep >= 0.0 ? 1.0 : -1.0;
    const double angle = std::atan2(q.y() - e.center.y(), q.x() - e.center.x());
    // Angle travelled from the start in the direction of the sweep, in [0, 2 pi).
    double travelled = std::fmod(side * (angle - e.start_angle), 2.0 * M_PI);
    if (travelled < 0.0) travelled += 2.0 * M_PI;
    const double candidate = travelled * e.radius;
    if (candidate >= s_lo && candidate <= s_hi) {
      local = candidate;
    } else {
      // Outside the arc or the search window: the nearer window end by angular distance around
      // the circle (the distance to a point of the circle grows with that angle). Clamping
      // `candidate` instead would pick the far end for a point just before the window.
      const double gap_lo = std::abs(wrapAngle((candidate - s_lo) / e.radius));
      const double gap_hi = std::abs(wrapAngle((candidate - s_hi) / e.radius));
      local = gap_lo <= gap_hi ? s_lo : s_hi;
    }
  }
  local = std::clamp(local, s_lo, s_hi);
  PathProjection p;
  p.point = pointOn(e, local, 0);
  p.s = e.s_start + local;
  const Vec2 d = q - p.point.position;
  p.distance = d.norm();
  p.cross_track = cross(unitVector(p.point.tangent), d) >= 0.0 ? p.distance : -p.distance;
  return p;
}

PathProjection Path::project(const Vec2& query, double s_min, double s_max) const {
  PathProjection best;
  best.distance = std::numeric_limits<double>::infinity();
  if (elements_.empty() || !(s_max >= s_min)) return best;
  if (!closed_) {
    s_min = std::clamp(s_min, 0.0, length_);
    s_max = std::clamp(s_max, 0.0, length_);
  }
  // Walk the laps covered by [s_min, s_max]; each lap's elements are clipped to the range.
  const double lap_first = closed_ ? std::floor(s_min / length_) : 0.0;
  const double lap_last = closed_ ? std::floor(s_max / length_) : 0.0;
  for (double lap = lap_first; lap <= lap_last; lap += 1.0) {
    const double offset = lap * length_;
    for (size_t i = 0; i < elements_.size(); ++i) {
      const PathElement& e = elements_[i];
      const double lo = std::max(0.0, s_min - offset - e.s_start);
      const double hi = std::min(e.length, s_max - offset - e.s_start);
      if (lo > hi) continue;
      PathProjection p = projectOnElement(e, query, lo, hi);
      if (p.distance < best.distance) {
        best = p;
        best.s += offset;
        best.point.element = static_cast<int>(i);
      }
    }
  }
  return best;
}

Path Path::transformed(const Vec2& offset, double yaw) const {
  const Eigen::Rotation2Dd rotation(yaw);
  Path out;
  for (const PathElement& e : elements_) {
    if (e.kind == PathElement::Kind::Line)
      out.appendLine(rotation * e.start + offset, rotation * e.end + offset);
    else
      out.appendArc(rotation * e.center + offset, e.radius, e.start_angle + yaw, e.sweep);
  }
  out.setClosed(closed_);
  return out;
}

std::vector<Vec2> Path::sample(double spacing) const {
  std::vector<Vec2> points;
  if (elements_.empty() || !(spacing > 0.0)) return points;
  for (size_t i = 0; i < elements_.size(); ++i) {
    const PathElement& e = elements_[i];
    const int n = std::max(1, static_cast<int>(std::ceil(e.length / spacing)));
    for (int k = 0; k < n; ++k) points.push_back(pointOn(e, e.length * k / n, i).position);
  }
  points.push_back(closed_ ? elements_.front().start : elements_.back().end);
  return points;
}

double Path::turnAfter(int i) const {
  const int n = static_cast<int>(elements_.size());
  if (i < 0 || i >= n) return 0.0;
  if (i == n - 1 && !closed_) return 0.0;
  const PathElement& a = elements_[i];
  const PathElement& b = elements_[(i + 1) % n];
  const double end_tangent = pointOn(a, a.length, i).tangent;
  const double start_tangent = pointOn(b, 0.0, i + 1).tangent;
  return wrapAngle(start_tangent - end_tangent);
}

}  // namespace flagella::control
