// The sparse Newton system's linear solver (docs/model.md 1.10): the 4x4-block LU
// (BlockSparseLu, no pivoting across blocks) when the DOFs are grouped into blocks, KLU with
// partial pivoting (SparseLuSolver) otherwise and whenever a block factorisation refuses its
// pivots. Either way the symbolic analysis is made once per sparsity pattern.
#pragma once

#include <vector>

#include "flagella_sim/rod/rod_network.h"
#include "flagella_sim/solver/block_sparse_lu.h"
#include "flagella_sim/solver/sparse_lu_solver.h"

namespace flagella {

class JacobianSolver {
 public:
  /// DOF groups for the block LU (see BlockSparseLu); empty: KLU only.
  void setBlocks(std::vector<BlockSparseLu::DofGroup> groups);
  /// Symbolic analysis for A's pattern (call before the first factorisation and whenever the
  /// pattern changes).
  void analyze(const SparseMatrix& A);
  /// Numeric factorisation; false if A is singular for KLU too. try_block = false: KLU only.
  bool factorize(const SparseMatrix& A, bool try_block = true);
  /// After a block LU factorisation (lastWasBlock()), A can be assembled in place, in
  /// blockLu()'s storage (BlockSparseLu::clearStorage), and factored by factorizeInPlace().
  BlockSparseLu& blockLu() { return block_; }
  /// Factors the values assembled in the block LU's storage; false if the block LU refuses them
  /// (the caller then assembles A and calls factorize(A, false): KLU).
  bool factorizeInPlace();
  /// Solves A x = b with the last factorisation.
  VecX solve(const VecX& b);
  /// The same into x (the block LU reuses x's storage).
  void solve(const VecX& b, VecX& x);

  /// Whether the last factorisation was the block LU's (else KLU's).
  bool lastWasBlock() const { return last_was_block_; }
  int blockFactorizations() const { return block_factorizations_; }
  /// Factorisations the block LU refused and KLU made instead.
  int blockFallbacks() const { return block_fallbacks_; }
  const SparseLuSolver& klu() const { return klu_; }
  const BlockSparseLu& blockLu() const { return block_; }

 private:
  /// Counts a block LU factorisation or its refusal, records which LU holds the factors.
  bool countBlockAttempt(bool accepted);

  std::vector<BlockSparseLu::DofGroup> groups_;
  BlockSparseLu block_;
  SparseLuSolver klu_;
  bool last_was_block_ = false;
  int block_factorizations_ = 0;
  int block_fallbacks_ = 0;
};

/// DOF groups of a rod network for the block LU: each node's three coordinates with the twist of
/// one of its edges (an edge's start node if free, else its end node, else a group of its own).
std::vector<BlockSparseLu::DofGroup> nodeEdgeBlocks(const RodNetwork& net);

}  // namespace flagella
