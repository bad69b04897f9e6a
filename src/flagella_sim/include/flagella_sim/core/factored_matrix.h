// A square matrix handed over together with a way to solve with it (its factorisation): what a
// dense Jacobian block of the form diag(w) A^{-1} needs, so that neither A^{-1} nor a second
// factorisation is ever formed by the receiver (docs/model.md 4.4).
#pragma once

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/core/types.h"

namespace flagella {

class FactoredMatrix {
 public:
  virtual ~FactoredMatrix() = default;
  /// A.
  virtual const MatX& matrix() const = 0;
  /// A^{-1} b.
  virtual VecX solveWith(const VecX& b) const = 0;
  /// A v (a matrix held in a factored or rotated form may do it without forming A).
  virtual VecX multiply(const VecX& v) const { return matrix() * v; }
  /// A^{-1} (O(n^3): for checks and fallbacks); by default column by column from solveWith.
  virtual MatX inverse() const {
    const int n = static_cast<int>(matrix().rows());
    MatX inv(n, n);
    VecX unit = VecX::Zero(n);
    for (int c = 0; c < n; ++c) {
      unit(c) = 1.0;
      inv.col(c) = solveWith(unit);
      unit(c) = 0.0;
    }
    return inv;
  }
};

/// A matrix and its partial-pivot LU (DenseLuSolver), held together.
class LuFactoredMatrix : public FactoredMatrix {
 public:
  /// Factors `a`; false (and unusable) if it is singular.
  bool factorize(MatX a) {
    a_ = std::move(a);
    return lu_.factorize(a_);
  }
  const MatX& matrix() const override { return a_; }
  VecX solveWith(const VecX& b) const override { return lu_.solve(b); }
  MatX inverse() const override { return lu_.inverse(); }

 private:
  MatX a_;
  DenseLuSolver lu_;
};

}  // namespace flagella
