#include "flagella_sim/solver/jacobian_solver.h"

namespace flagella {

void JacobianSolver::setBlocks(std::vector<BlockSparseLu::DofGroup> groups) {
  groups_ = std::move(groups);
  block_ = BlockSparseLu();
}

void JacobianSolver::analyze(const SparseMatrix& A) {
  if (!groups_.empty()) block_.analyze(A, groups_);
  klu_.analyze(A);
}

bool JacobianSolver::countBlockAttempt(bool accepted) {
  ++(accepted ? block_factorizations_ : block_fallbacks_);
  last_was_block_ = accepted;
  return accepted;
}

bool JacobianSolver::factorizeInPlace() {
  return countBlockAttempt(block_.factorizeInPlace(SparseLuSolver::kMinPivotRatio));
}

bool JacobianSolver::factorize(const SparseMatrix& A, bool try_block) {
  // Refused below the pivot ratio at which KLU itself re-pivots.
  if (try_block && !groups_.empty() &&
      countBlockAttempt(block_.factorize(A, SparseLuSolver::kMinPivotRatio)))
    return true;
  last_was_block_ = false;
  return klu_.factorize(A);
}

VecX JacobianSolver::solve(const VecX& b) {
  return last_was_block_ ? block_.solve(b) : klu_.solve(b);
}

void JacobianSolver::solve(const VecX& b, VecX& x) {
  if (last_was_block_)
    block_.solve(b, x);
  else
    x = klu_.solve(b);
}

std::vector<BlockSparseLu::DofGroup> nodeEdgeBlocks(const RodNetwork& net) {
  std::vector<BlockSparseLu::DofGroup> groups(net.numNodes());
  for (int n = 0; n < net.numNodes(); ++n)
    groups[n] = {RodNetwork::positionIndex(n), RodNetwork::positionIndex(n) + 1,
                 RodNetwork::positionIndex(n) + 2, -1};
  for (int e = 0; e < net.numEdges(); ++e) {
    int* slot = nullptr;
    for (int node : {net.edges[e].start_node, net.edges[e].end_node})
      if (!slot && groups[node][3] < 0) slot = &groups[node][3];
    if (slot)
      *slot = net.thetaIndex(e);
    else
      groups.push_back({net.thetaIndex(e), -1, -1, -1});
  }
  return groups;
}

}  // namespace flagella
