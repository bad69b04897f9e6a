#include "flagella_sim/elastic/stretching_energy.h"

namespace flagella {

double stretchingEnergy(const RodNetwork& net, const VecX& q) {
  double energy = 0.0;
  for (const StretchSpring& s : net.stretch_springs) {
    const EdgeDef& e = net.edges[s.edge];
    const double len = (nodePosition(q, e.end_node) - nodePosition(q, e.start_node)).norm();
    const double strain = len / s.rest_length - 1.0;         // docs/model.md 1.3
    energy += 0.5 * s.EA * strain * strain * s.rest_length;  // docs/model.md 1.4
  }
  return energy;
}

void addStretchingGradientHessian(const RodNetwork& net, const ReferenceFrames& frames,
                                  VecX& gradient, SparseAssembler* hessian) {
  for (const StretchSpring& s : net.stretch_springs) {
    const EdgeDef& e = net.edges[s.edge];
    const double len = frames.edge_length[s.edge];
    const Vec3& t = frames.tangent[s.edge];
    // docs/model.md 1.5: dE/dx_b = EA (l/lbar - 1) t = -dE/dx_a
    // (a true division: the strain of a stiff edge is a small difference, one rounding only)
    const Vec3 g = (s.EA * (len / s.rest_length - 1.0)) * t;
    const int a = 3 * e.start_node, b = 3 * e.end_node;
    gradient.segment<3>(a) -= g;
    gradient.segment<3>(b) += g;
    if (!hessian) continue;
    // docs/model.md 1.5: K = EA [ (1/lbar - 1/l) I + (1/l) t t^T ]
    const double inv_len = 1.0 / len;
    Mat3 K = (s.EA * inv_len) * (t * t.transpose());
    K.diagonal().array() += s.EA * (1.0 / s.rest_length - inv_len);
    hessian->addBlock(a, a, K);
    hessian->subtractBlock(a, b, K);
    hessian->subtractBlock(b, a, K);
    hessian->addBlock(b, b, K);
  }
}

}  // namespace flagella
