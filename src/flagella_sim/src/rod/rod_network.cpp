#include "flagella_sim/rod/rod_network.h"

namespace flagella {

VecX RodNetwork::restDofs() const {
  VecX q = VecX::Zero(ndof());
  for (int i = 0; i < numNodes(); ++i) q.segment<3>(3 * i) = rest_positions[i];
  return q;
}

}  // namespace flagella
