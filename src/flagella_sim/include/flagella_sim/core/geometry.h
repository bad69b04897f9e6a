// Small vector-geometry helpers used by the rod kinematics (spec section 1.3).
#pragma once

#include <cmath>

#include "flagella_sim/core/types.h"

namespace flagella {

/// Cross-product matrix [a]x, so that skew(a) * b == a.cross(b).
Mat3 skew(const Vec3& a);

/// v / |v| with one division (Eigen's normalized() divides each coefficient); v must not be 0.
inline Vec3 unitVector(const Vec3& v) { return v * (1.0 / v.norm()); }

/// Below this |a x b| two unit tangents are treated as parallel (transport is the identity).
constexpr double kParallelTransportTolerance = 1e-14;

/// Parallel transport of u from unit tangent a to unit tangent b (docs/model.md 1.3).
/// Returns u unchanged when a and b are (nearly) parallel. Inline: the frame transport calls it
/// twice per edge and Newton iterate.
inline Vec3 parallelTransport(const Vec3& u, const Vec3& a, const Vec3& b) {
  // docs/model.md 1.3: the rotation about a x b taking a to b, in Rodrigues' form without
  // trigonometry: P(u) = c u + (a x b) x u + ((a x b).u / (1 + c)) (a x b), c = a.b
  const Vec3 axis = a.cross(b);
  const double c = a.dot(b);
  if (axis.squaredNorm() < kParallelTransportTolerance * kParallelTransportTolerance) return u;
  return c * u + axis.cross(u) + (axis.dot(u) / (1.0 + c)) * axis;
}

/// Unsigned angle between u and v in [0, pi]: atan2(|u x v|, u.v), accurate for small angles
/// (unlike acos).
double angleBetween(const Vec3& u, const Vec3& v);

/// Signed angle from u to v about the unit axis n when both lie in the plane normal to n:
/// atan2(n.(u x v), u.v), in (-pi, pi] (docs/model.md 1.3).
inline double angleAbout(const Vec3& u, const Vec3& v, const Vec3& n) {
  return std::atan2(n.dot(u.cross(v)), u.dot(v));
}

/// Any unit vector perpendicular to the unit vector t.
Vec3 anyPerpendicular(const Vec3& t);

}  // namespace flagella
