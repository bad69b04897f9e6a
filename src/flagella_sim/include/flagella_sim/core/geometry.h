// Small vector-geometry helpers used by the rod kinematics (spec section 1.3).
#pragma once

#include "flagella_sim/core/types.h"

namespace flagella {

/// Cross-product matrix [a]x, so that skew(a) * b == a.cross(b).
Mat3 skew(const Vec3& a);

/// Parallel transport of u from unit tangent a to unit tangent b (docs/model.md 1.3).
/// Returns u unchanged when a and b are (nearly) parallel.
Vec3 parallelTransport(const Vec3& u, const Vec3& a, const Vec3& b);

/// Unsigned angle between u and v in [0, pi]: atan2(|u x v|, u.v), accurate for small angles
/// (unlike acos).
double angleBetween(const Vec3& u, const Vec3& v);

/// Signed angle from u to v about the unit axis n when both lie in the plane normal to n:
/// atan2(n.(u x v), u.v), in (-pi, pi] (docs/model.md 1.3).
double angleAbout(const Vec3& u, const Vec3& v, const Vec3& n);

/// Any unit vector perpendicular to the unit vector t.
Vec3 anyPerpendicular(const Vec3& t);

}  // namespace flagella
