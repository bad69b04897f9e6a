// Regularized Stokeslet segment (RSS) integrals and 3x3 blocks for one segment with linear force
// density (docs/model.md 4.1-4.2; Cortez, J. Comput. Phys. 375 (2018) "Regularized Stokeslet
// segments").
#pragma once

#include "flagella_sim/core/types.h"

namespace flagella::rss {

/// T_{k,-m} = integral_0^1 alpha^k R_alpha^{-m} d alpha, R_alpha^2 = |r_i + alpha v|^2 + eps^2.
struct SegmentIntegrals {
  double t0m1 = 0, t1m1 = 0;                      // T_{0,-1}, T_{1,-1}
  double t0m3 = 0, t1m3 = 0, t2m3 = 0, t3m3 = 0;  // T_{0,-3} .. T_{3,-3}
};

/// Closed forms of docs/model.md 4.2 with the stable rewrite of 4.5. r_i = xt - x_i, v = x_i -
/// x_{i+1} (must be non-zero), eps > 0. Inputs are not validated here (hot path): see rss_matrix.h.
SegmentIntegrals segmentIntegrals(const Vec3& r_i, const Vec3& v, double eps);

/// A segment x_i -> x_{i+1} as every evaluation point sees it: v = x_i - x_{i+1}, Dl^2, Dl, 1/Dl,
/// 1/Dl^2.
struct SegmentGeometry {
  SegmentGeometry(const Vec3& x_i, const Vec3& x_ip1);
  Vec3 v;
  double dl2, dl, inv_dl, inv_dl2;
};

/// The same integrals with the segment's geometry and both ends' R_alpha = sqrt(|xt - x_end|^2 +
/// eps^2) given (R_0 at x_i, R_1 at x_{i+1}): an assembly over many points and segments computes
/// each node pair's R once (docs/model.md 4.2).
SegmentIntegrals segmentIntegrals(const Vec3& r_i, const SegmentGeometry& segment, double r_0,
                                  double r_1, double eps);

/// The blocks A1 (multiplies f_i) and A2 (multiplies f_{i+1}) of docs/model.md 4.2, so that the
/// segment x_i -> x_{i+1} induces 8 pi mu u(xt) = Dl (A1 f_i + A2 f_{i+1}), Dl = |x_{i+1} - x_i|.
struct SegmentBlocks {
  Mat3 a1 = Mat3::Zero();
  Mat3 a2 = Mat3::Zero();
};
SegmentBlocks segmentBlocks(const Vec3& xt, const Vec3& x_i, const Vec3& x_ip1, double eps);

/// A1 and A2 are symmetric: each is d I + c_rr r r^T + c_rv (r v^T + v r^T) + c_vv v v^T with
/// r = r_i, v = x_i - x_{i+1}. Their coefficients times `scale` (docs/model.md 4.2).
struct SegmentBlockCoefficients {
  double d1, rr1, rv1, vv1;  ///< of A1
  double d2, rr2, rv2, vv2;  ///< of A2
};
SegmentBlockCoefficients segmentBlockCoefficients(const SegmentIntegrals& t, double eps,
                                                  double scale);

/// 8 pi mu u(xt) induced by the segment with nodal force densities f_i, f_ip1 (docs/model.md 4.2).
Vec3 segmentVelocityTimes8PiMu(const Vec3& xt, const Vec3& x_i, const Vec3& x_ip1, const Vec3& f_i,
                               const Vec3& f_ip1, double eps);

}  // namespace flagella::rss
