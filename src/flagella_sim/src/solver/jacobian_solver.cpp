#include "flagella_sim/solver/jacobian_solver.h"

namespace flagella {

namespace {
// A block factorisation whose smallest pivot is below this times its largest is refused, the
// threshold below which SparseLuSolver re-pivots a refactorisation.
constexpr double kMinPivotRatio = 1e-13;
}  // namespace

void JacobianSolver::setBlocks(std::vector<BlockSparseLu::DofGroup> groups) {
  groups_ = std::move(groups);
  block_ = BlockSparseLu();
}

void JacobianSolver::analyze(const SparseMatrix& A) {
  if (!groups_.empty()) block_.analyze(A, groups_);
  klu_analyzed_ = false;  // analysed on KLU's first use
}

bool JacobianSolver::factorize(const SparseMatrix& A) {
  if (!groups_.empty()) {
    if (!block_.analyzed()) block_.analyze(A, groups_);
    if (block_.factorize(A, kMinPivotRatio)) {
      ++block_factorizations_;
      last_was_block_ = true;
      return true;
    }
    ++block_fallbacks_;
  }
  last_was_block_ = false;
  if (!klu_analyzed_) {
    klu_.analyze(A);
    klu_analyzed_ = true;
  }
  return klu_.factorize(A);
}

VecX JacobianSolver::solve(const VecX& b) {
  return last_was_block_ ? block_.solve(b) : klu_.solve(b);
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
