#include "flagella_sim/hydro/segment_integrals.h"

#include <cmath>

namespace flagella::rss {
namespace {

// One end (alpha = 0 or 1) of the segment, as seen from the evaluation point.
struct End {
  double R;     // R_alpha
  double rv;    // r_alpha . v
  double G;     // Dl R_alpha + |r_alpha . v|: never suffers cancellation
  bool behind;  // r_alpha . v < 0: Dl R + r.v would cancel (docs/model.md 4.5)
};

End endAt(double R, double rv, double dl) {
  End e;
  e.R = R;
  e.rv = rv;
  e.G = dl * e.R + std::abs(rv);
  e.behind = rv < 0.0;
  return e;
}

// 1/(R (Dl R + r.v)) without its constant part: for r.v < 0, the rewrite of docs/model.md 4.5,
// Dl R + r.v = Dl^2 rho^2 / (Dl R - r.v) (rho^2 = |r_perp|^2 + eps^2), gives
// 1/(R (Dl R + r.v)) = 2/(Dl rho^2) - 1/(R (Dl R - r.v)); the constant 2/(Dl rho^2) is added
// separately so that it cancels exactly when both ends are behind.
double inverseRgRegular(const End& e) { return (e.behind ? -1.0 : 1.0) / (e.R * e.G); }

}  // namespace

SegmentGeometry::SegmentGeometry(const Vec3& x_i, const Vec3& x_ip1)
    : v(x_i - x_ip1),
      dl2(v.squaredNorm()),
      dl(std::sqrt(dl2)),
      inv_dl(1.0 / dl),
      inv_dl2(1.0 / dl2) {}

SegmentIntegrals segmentIntegrals(const Vec3& r_i, const Vec3& v, double eps) {
  const SegmentGeometry segment(Vec3::Zero(), -v);
  const double e2 = eps * eps;
  return segmentIntegrals(r_i, segment, std::sqrt(r_i.squaredNorm() + e2),
                          std::sqrt((r_i + v).squaredNorm() + e2), eps);
}

SegmentIntegrals segmentIntegrals(const Vec3& r_i, const SegmentGeometry& segment, double r_0,
                                  double r_1, double eps) {
  const Vec3& v = segment.v;
  const double dl2 = segment.dl2, dl = segment.dl, inv_dl2 = segment.inv_dl2;
  const double riv = r_i.dot(v);
  const Vec3 r_perp = r_i - (riv * inv_dl2) * v;  // the same for every alpha
  const double rho2 = r_perp.squaredNorm() + eps * eps;
  const End e0 = endAt(r_0, riv, dl);
  const End e1 = endAt(r_1, riv + dl2, dl);
  // r_alpha.v grows with alpha, so only e0 can be behind while e1 is not.
  const bool mixed = e0.behind && !e1.behind;

  SegmentIntegrals t;
  // T_{0,-1} = (1/Dl) [ln(Dl R + r.v)]_0^1 (docs/model.md 4.2), each log through the rewrite
  // of 4.5.
  double log_ratio;
  if (mixed) {
    log_ratio = std::log(e1.G * e0.G / (dl2 * rho2));
  } else if (e0.behind) {
    log_ratio = std::log(e0.G / e1.G);
  } else {
    log_ratio = std::log(e1.G / e0.G);
  }
  t.t0m1 = log_ratio * segment.inv_dl;
  // T_{0,-3} = -[1/(R (Dl R + r.v))]_0^1 (docs/model.md 4.2 with the rewrite of 4.5).
  t.t0m3 = -(inverseRgRegular(e1) - inverseRgRegular(e0)) + (mixed ? 2.0 / (dl * rho2) : 0.0);
  // [R]_0^1 = (R_1^2 - R_0^2)/(R_1 + R_0) = (2 r_i.v + Dl^2)/(R_1 + R_0): no cancellation.
  const double dR = (2.0 * riv + dl2) / (e1.R + e0.R);
  const double inv_r0 = 1.0 / e0.R, inv_r1 = 1.0 / e1.R;
  const double dInvR = -dR * inv_r0 * inv_r1;  // [1/R]_0^1
  // Recursions of docs/model.md 4.2 (integration by parts, d R/d alpha = r_alpha.v / R).
  const double c = riv * inv_dl2;
  t.t1m1 = (dR - riv * t.t0m1) * inv_dl2;
  t.t1m3 = (-dInvR - riv * t.t0m3) * inv_dl2;
  t.t2m3 = (-inv_r1 + t.t0m1) * inv_dl2 - c * t.t1m3;
  t.t3m3 = (-inv_r1 + 2.0 * t.t1m1) * inv_dl2 - c * t.t2m3;
  return t;
}

SegmentBlockCoefficients segmentBlockCoefficients(const SegmentIntegrals& t, double eps,
                                                  double scale) {
  const double e2 = eps * eps;
  // A2 = (T1,-1 + e2 T1,-3) I + T1,-3 rr + T2,-3 (rv + vr) + T3,-3 vv; A1 = A1' - A2 with
  // A1' = (T0,-1 + e2 T0,-3) I + T0,-3 rr + T1,-3 (rv + vr) + T2,-3 vv (intercept/slope into
  // nodal values)
  SegmentBlockCoefficients c;
  c.d2 = scale * (t.t1m1 + e2 * t.t1m3);
  c.rr2 = scale * t.t1m3;
  c.rv2 = scale * t.t2m3;
  c.vv2 = scale * t.t3m3;
  c.d1 = scale * (t.t0m1 + e2 * t.t0m3) - c.d2;
  c.rr1 = scale * t.t0m3 - c.rr2;
  c.rv1 = scale * t.t1m3 - c.rv2;
  c.vv1 = scale * t.t2m3 - c.vv2;
  return c;
}

SegmentBlocks segmentBlocks(const Vec3& xt, const Vec3& x_i, const Vec3& x_ip1, double eps) {
  const Vec3 r = xt - x_i;
  const Vec3 v = x_i - x_ip1;
  const SegmentBlockCoefficients c =
      segmentBlockCoefficients(segmentIntegrals(r, v, eps), eps, 1.0);
  const Mat3 rr = r * r.transpose();
  const Mat3 rv_vr = r * v.transpose() + v * r.transpose();
  const Mat3 vv = v * v.transpose();
  SegmentBlocks b;
  b.a1 = c.d1 * Mat3::Identity() + c.rr1 * rr + c.rv1 * rv_vr + c.vv1 * vv;
  b.a2 = c.d2 * Mat3::Identity() + c.rr2 * rr + c.rv2 * rv_vr + c.vv2 * vv;
  return b;
}

Vec3 segmentVelocityTimes8PiMu(const Vec3& xt, const Vec3& x_i, const Vec3& x_ip1, const Vec3& f_i,
                               const Vec3& f_ip1, double eps) {
  const SegmentBlocks b = segmentBlocks(xt, x_i, x_ip1, eps);
  return (x_ip1 - x_i).norm() * (b.a1 * f_i + b.a2 * f_ip1);
}

}  // namespace flagella::rss
