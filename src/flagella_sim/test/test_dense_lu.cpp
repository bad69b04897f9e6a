// The dense LU (LAPACK) used for RSS and dense Newton systems: solves and inverts non-symmetric
// matrices (residual checks), refuses singular or non-finite ones.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "flagella_sim/core/dense_lu_solver.h"

namespace flagella {
namespace {

MatX randomMatrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  return MatX::NullaryExpr(n, n, [&] { return g(rng); });
}

TEST(DenseLu, SolvesAndInvertsNonSymmetricSystems) {
  for (int n : {1, 7, 120}) {
    const MatX A = randomMatrix(n, 3 + n);
    if (n > 1) ASSERT_GT((A - A.transpose()).norm(), 1.0);  // not symmetric
    const VecX x = VecX::LinSpaced(n, -1.0, 2.0);
    DenseLuSolver lu;
    ASSERT_TRUE(lu.factorize(A));
    EXPECT_GT(lu.rcond(), 0.0);
    const VecX b = A * x;
    EXPECT_LT((A * lu.solve(b) - b).norm(), 1e-12 * A.norm() * x.norm());  // backward error
    EXPECT_LT((lu.inverse() * A - MatX::Identity(n, n)).norm(), 1e-8);
  }
}

TEST(DenseLu, RefusesSingularAndNonFiniteMatrices) {
  MatX A = randomMatrix(6, 11);
  A.row(4) = 2.0 * A.row(1);
  DenseLuSolver lu;
  EXPECT_FALSE(lu.factorize(A));
  A = randomMatrix(6, 12);
  A(2, 3) = std::nan("");
  EXPECT_FALSE(lu.factorize(A));
  A = MatX::Identity(3, 3);
  A(2, 2) = 1e-18;  // rcond 1e-18 below the default threshold 1e-15
  EXPECT_FALSE(lu.factorize(A));
  EXPECT_TRUE(lu.factorize(A, 1e-20));
}

}  // namespace
}  // namespace flagella
