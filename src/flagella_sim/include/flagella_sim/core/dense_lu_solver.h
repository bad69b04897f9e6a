// Dense LU with partial pivoting for square systems that are not symmetric (the Newton Jacobian
// with an RSS block, the RSS matrix itself; docs/model.md 4.3-4.4), backed by LAPACK (dgetrf,
// dgetrs, dgetri, dgecon) from OpenBLAS, run on one thread so parallel runs do not compete.
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

class DenseLuSolver {
 public:
  /// Factors A (copied); false if A is singular, not finite, or its reciprocal condition number
  /// estimate is below `min_rcond`.
  bool factorize(const MatX& A, double min_rcond = 1e-15);
  /// The same, factoring A in place (no copy); A is left holding unspecified values (the
  /// storage of the previous factorisation, to reuse).
  bool factorize(MatX&& A, double min_rcond = 1e-15);
  /// Solves A x = b with the last factorisation.
  VecX solve(const VecX& b) const;
  /// Solves A^T x = b with the last factorisation.
  VecX solveTransposed(const VecX& b) const;
  /// A^{-1} from the last factorisation.
  MatX inverse() const;
  /// Reciprocal condition number estimate (1-norm) of the last factorised matrix; with
  /// estimateConditionOnlyIfPivotsSpread(), the pivot ratio when the estimate was skipped.
  double rcond() const { return rcond_; }
  /// Takes the condition estimate (dgecon, about half an LU's time on the helical robot's
  /// matrices) only when the pivots' magnitudes spread by more than kEstimatePivotRatio;
  /// otherwise the factorisation is accepted on its pivots (for the solvers called every
  /// Newton update, docs/model.md 1.10). Default off: every factorisation is estimated.
  void estimateConditionOnlyIfPivotsSpread(bool on) { pivot_gate_ = on; }
  /// Pivot ratio min |u_ii| / max |u_ii| below which the estimate is always taken.
  static constexpr double kEstimatePivotRatio = 1e-6;
  int size() const { return static_cast<int>(lu_.rows()); }

 private:
  /// Checks A (square, finite) and records its 1-norm; false if not finite.
  bool checkInput(const MatX& A);
  /// dgetrf and dgecon on lu_.
  bool factorizeStored(double min_rcond);
  VecX solveWith(char trans, const VecX& b) const;

  MatX lu_;
  std::vector<int> pivots_;
  double rcond_ = 0.0;
  double anorm_ = 0.0;
  std::vector<double> work_;
  std::vector<int> iwork_;
  bool pivot_gate_ = false;
};

}  // namespace flagella
