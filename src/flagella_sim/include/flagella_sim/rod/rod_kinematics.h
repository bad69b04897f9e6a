// Frames, material directors and per-spring strains of a rod network at a DOF vector
// (docs/model.md 1.3, 1.6, 1.7).
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"
#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/rod/rod_state.h"

namespace flagella {

/// Builds t = 0 frames by space-parallel transport along the tree from the root edge,
/// and measures each spring's initial reference twist directly (docs/model.md 1.7).
ReferenceFrames initialFrames(const RodNetwork& net, const VecX& q, int root_edge = 0);

/// Time-parallel transport of every reference frame from `previous` (at the start of the step)
/// to the tangents of q, with the reference twist tracked incrementally (docs/model.md 1.3, 1.7).
ReferenceFrames transportFrames(const RodNetwork& net, const VecX& q,
                                const ReferenceFrames& previous);
/// The same into `out` (its storage reused; `out` must not be `previous`).
void transportFrames(const RodNetwork& net, const VecX& q, const ReferenceFrames& previous,
                     ReferenceFrames& out);

/// Local-representation quantities of one bending-twisting spring (docs/model.md 1.3, 1.6).
struct SpringGeometry {
  double len_e, len_f;      ///< lengths of the local edges e = x_c - x_p, f = x_q - x_c
  Vec3 te, tf;              ///< local unit tangents
  Vec3 m1e, m2e, m1f, m2f;  ///< local material directors
  Vec3 kb;                  ///< curvature binormal
  double kappa1, kappa2, tau;
};

/// Material directors of every edge (stored orientation): m1 = cos(theta) d1 + sin(theta) d2,
/// m2 = -sin(theta) d1 + cos(theta) d2 (docs/model.md 1.2).
struct MaterialFrames {
  std::vector<Vec3> m1, m2;
};
/// Fills `out` (its storage reused) from q and the reference frames.
void materialFrames(const RodNetwork& net, const VecX& q, const ReferenceFrames& frames,
                    MaterialFrames& out);

/// Evaluates one spring's local geometry from q, the reference frames and its ref. twist.
/// `frames` must be those of q (initialFrames or transportFrames of this q): their tangents and
/// edge lengths are used.
SpringGeometry springGeometry(const RodNetwork& net, const BendTwistSpring& spring, const VecX& q,
                              const ReferenceFrames& frames, int spring_index);
/// The same with the edges' material directors already computed (one cos/sin per edge instead of
/// two per spring).
SpringGeometry springGeometry(const RodNetwork& net, const BendTwistSpring& spring, const VecX& q,
                              const ReferenceFrames& frames, const MaterialFrames& material,
                              int spring_index);

/// The bending-twisting spring whose local edges turn the most, and that turning angle [rad]
/// (pi: folded back on itself, where the curvature binormal diverges, docs/model.md 1.3).
/// spring -1 for a network without springs.
struct FoldedJoint {
  int spring = -1;
  double angle = 0.0;
};
FoldedJoint mostFoldedJoint(const RodNetwork& net, const ReferenceFrames& frames);

/// Material director m1^j (stored orientation) of edge j.
Vec3 materialDirector1(const ReferenceFrames& frames, const VecX& q, const RodNetwork& net,
                       int edge);

}  // namespace flagella
