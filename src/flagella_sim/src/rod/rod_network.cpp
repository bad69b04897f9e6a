#include "flagella_sim/rod/rod_network.h"

namespace flagella {

std::vector<double> RodNetwork::nodeVoronoiLengths() const {
  // spec 1.8: each node collects half of every undeformed edge that touches it
  std::vector<double> lengths(rest_positions.size(), 0.0);
  for (int j = 0; j < numEdges(); ++j) {
    lengths[edges[j].start_node] += 0.5 * rest_lengths[j];
    lengths[edges[j].end_node] += 0.5 * rest_lengths[j];
  }
  return lengths;
}

VecX RodNetwork::restDofs() const {
  VecX q = VecX::Zero(ndof());
  for (int i = 0; i < numNodes(); ++i) q.segment<3>(3 * i) = rest_positions[i];
  return q;
}

}  // namespace flagella
