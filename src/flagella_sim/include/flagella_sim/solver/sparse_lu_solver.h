// Sparse LU for the Newton Jacobian, backed by SuiteSparse KLU: the symbolic analysis is done
// once per sparsity pattern, the first numeric factorisation chooses pivots, and later ones
// refactor with the same pivot order (fast) unless the pivots have degraded, in which case the
// factorisation is redone with fresh pivoting.
#pragma once

#include "flagella_sim/core/types.h"

namespace flagella {

class SparseLuSolver {
 public:
  /// Below this reciprocal pivot ratio (KLU's rcond: smallest |U_kk| over largest) a reused pivot
  /// order is distrusted and a fresh pivoting factorisation is made.
  static constexpr double kMinPivotRatio = 1e-13;

  SparseLuSolver();
  ~SparseLuSolver();
  SparseLuSolver(const SparseLuSolver&) = delete;
  SparseLuSolver& operator=(const SparseLuSolver&) = delete;

  /// Symbolic analysis of A's pattern (call when the pattern changes).
  void analyze(const SparseMatrix& A);
  /// Numeric factorisation; false if A is singular.
  bool factorize(const SparseMatrix& A);
  /// Solves A x = b with the last factorisation.
  VecX solve(const VecX& b);
  /// Solves A X = B in place for `nrhs` right-hand sides stored column by column (leading
  /// dimension `ldim` >= size); false without a factorisation or on a KLU error.
  bool solveInPlace(double* b, int ldim, int nrhs);
  /// KLU's reciprocal pivot ratio (smallest |U_kk| over largest) of the last factorisation.
  double pivotRatio();

  int numericFactorizations() const { return full_factorizations_; }
  int refactorizations() const { return refactorizations_; }

 private:
  void freeNumeric();
  struct Impl;
  Impl* impl_;
  int full_factorizations_ = 0;
  int refactorizations_ = 0;
};

}  // namespace flagella
