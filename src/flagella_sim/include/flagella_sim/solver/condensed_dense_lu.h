// LU of a Newton matrix whose columns are dense only on a set H of DOFs (the preconditioned
// flagellum positions, docs/model.md 4.4) by condensing out the other DOFs S first:
//   M = [M_HH M_HS; M_SH M_SS], the S columns sparse (those of the sparse Jacobian),
//   Schur complement M_HH - M_HS M_SS^{-1} M_SH factored densely (partial-pivot LU),
// so that the dense work is |H|^3 instead of (|H| + |S|)^3. There is no pivoting across H and S:
// factorize() refuses (returns false) when M_SS or the complement is near singular, and the
// caller then factors the whole matrix.
#pragma once

#include <memory>
#include <vector>

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/core/types.h"

namespace flagella {

class SparseLuSolver;

class CondensedDenseLu {
 public:
  using RowMajorMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  CondensedDenseLu();
  ~CondensedDenseLu();
  CondensedDenseLu(const CondensedDenseLu&) = delete;
  CondensedDenseLu& operator=(const CondensedDenseLu&) = delete;

  /// Factors M with M(:, dense_dofs[k]) = dense_columns(:, k) (n x |H|, dense_dofs distinct) and
  /// M(:, j) = sparse(:, j) for every other column j. False when a block is singular or its
  /// reciprocal condition estimate (KLU's pivot ratio for M_SS) is below `min_rcond`.
  bool factorize(const SparseMatrix& sparse, const std::vector<int>& dense_dofs,
                 const RowMajorMatX& dense_columns, double min_rcond);
  /// Solves M x = rhs in place with the last successful factorisation.
  void solveInPlace(VecX& rhs) const;

 private:
  void partition(int n, const std::vector<int>& dense_dofs);
  /// M_SS and M_HS (compressed columns) from the sparse columns; true when M_SS's pattern
  /// changed (a new symbolic analysis is needed).
  bool gatherSparseBlocks(const SparseMatrix& sparse);

  std::vector<int> dense_;   ///< H, in the order of the dense columns
  std::vector<int> sparse_;  ///< S, ascending
  std::vector<int> slot_;    ///< DOF -> index in H (>= 0) or -1 - index in S
  SparseMatrix ss_, hs_;     ///< M_SS (|S| x |S|), M_HS (|H| x |S|)
  std::unique_ptr<SparseLuSolver> ss_lu_;
  MatX x_;                  ///< M_SS^{-1} M_SH (|S| x |H|), column-major for KLU
  RowMajorMatX x_rows_;     ///< the same, row-major for the complement's row updates
  MatX schur_t_;            ///< the complement's transpose (work storage of its LU)
  DenseLuSolver schur_lu_;  ///< LU of the complement's transpose
  mutable VecX ws_, wh_;
};

}  // namespace flagella
