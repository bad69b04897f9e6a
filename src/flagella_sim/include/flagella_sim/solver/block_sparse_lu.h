// Sparse LU on 4x4 blocks for the rod network's Newton Jacobian. The DOFs are grouped four to a
// block (a node's three coordinates and the twist of one of its edges, docs/model.md 1.10), the
// blocks are eliminated in an approximate-minimum-degree order of the block graph (SuiteSparse
// AMD; a tree-shaped network gets no fill), each diagonal block inverted after partial pivoting
// inside it. The pattern and the elimination schedule are computed once per sparsity pattern;
// a factorisation is then a fixed list of 4x4 block products that Eigen vectorises.
// No pivoting across blocks: factorize() refuses (returns false) when a diagonal block's pivots
// are tiny against the largest (the same reciprocal pivot ratio KLU's refactorisation checks),
// and the caller falls back to a pivoting sparse LU (JacobianSolver).
#pragma once

#include <array>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

class BlockSparseLu {
 public:
  using Block = Eigen::Matrix4d;
  /// A block's DOF indices; -1 pads a block with fewer than four DOFs (identity there).
  using DofGroup = std::array<int, 4>;

  /// Symbolic analysis of A's pattern with the DOFs grouped into `groups` (every DOF of A in
  /// exactly one group; throws std::invalid_argument otherwise).
  void analyze(const SparseMatrix& A, const std::vector<DofGroup>& groups);
  /// Numeric factorisation of A (same pattern as analysed); false if a pivot block is singular
  /// or its pivots are below `min_pivot_ratio` times the largest pivot, or a value is not finite.
  bool factorize(const SparseMatrix& A, double min_pivot_ratio);
  /// Assembly in place, without copying A's values: clearStorage() zeroes the factor's storage
  /// (and writes the padding units), the caller adds the value of A's k-th stored entry at
  /// storage()[valueOffsets()[k]], factorizeInPlace() factors what was added (the same
  /// arithmetic as factorize(A)). Valid until the next analyze().
  void clearStorage();
  double* storage() { return blocks_.empty() ? nullptr : blocks_[0].data(); }
  int storageSize() const { return 16 * static_cast<int>(blocks_.size()); }
  const std::vector<int>& valueOffsets() const { return value_offset_; }
  bool factorizeInPlace(double min_pivot_ratio);
  /// Solves A x = b with the last successful factorisation.
  VecX solve(const VecX& b);
  /// The same into x (resized; its storage reused across calls).
  void solve(const VecX& b, VecX& x);

  int numBlocks() const { return static_cast<int>(groups_.size()); }
  /// Off-diagonal blocks created by elimination (0 for a tree-shaped network).
  int fillBlocks() const { return fill_blocks_; }

 private:
  struct Update {  // blocks_[target] -= blocks_[lower] * blocks_[upper]
    int target, lower, upper;
  };
  std::vector<DofGroup> groups_;
  std::vector<int> order_;                 // elimination order of blocks
  std::vector<int> diagonal_;              // storage index of each block's diagonal block
  std::vector<int> lower_begin_;           // per step k: range in lower_ of blocks (i, order_[k])
  std::vector<std::array<int, 2>> lower_;  // (row block i, storage index of L_ik)
  std::vector<int> upper_begin_;           // per step k: range in upper_ of blocks (order_[k], j)
  std::vector<std::array<int, 2>> upper_;  // (column block j, storage index of U_kj)
  std::vector<int> update_begin_;          // per step k: range in updates_
  std::vector<Update> updates_;
  std::vector<int> value_offset_;  // per value of A: its stored entry (block * 16 + entry)
  std::vector<int> zero_offsets_;  // stored entries that start at 0 (fill and unused slots)
  std::vector<int> unit_offsets_;  // the padding DOFs' unit diagonals
  int nonzeros_ = 0;
  std::vector<unsigned> padding_;  // per block: bit s set if slot s is padding
  std::vector<Block> blocks_;
  std::vector<Block> inverse_diagonal_;  // per step k
  std::vector<Eigen::Vector4d> work_;    // per block, for solve()
  int ndof_ = 0;
  int fill_blocks_ = 0;
};

}  // namespace flagella
