// The dense LU (LAPACK) used for RSS and dense Newton systems: solves and inverts non-symmetric
// matrices (residual checks), refuses singular or non-finite ones. The dense Newton system with an
// inverse block solved without the inverse (right preconditioning) against the explicitly formed
// Jacobian, with and without Dirichlet DOFs, dense blocks and a second inverse block; the
// condensed LU (sparse DOFs eliminated first, Schur complement on the dense columns) against a
// dense LU of the same matrix, and its refusal of a singular sparse block, after which the Newton
// system factors the whole matrix.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/solver/condensed_dense_lu.h"
#include "flagella_sim/solver/dense_newton_system.h"
#include "support/random_matrices.h"

namespace flagella {
namespace {

using testing::randomMatrix;
using testing::randomVector;

TEST(DenseLu, SolvesAndInvertsNonSymmetricSystems) {
  for (int n : {1, 7, 120}) {
    const MatX A = randomMatrix(n, 3 + n);
    if (n > 1) {
      ASSERT_GT((A - A.transpose()).norm(), 1.0);  // not symmetric
    }
    const VecX x = VecX::LinSpaced(n, -1.0, 2.0);
    DenseLuSolver lu;
    ASSERT_TRUE(lu.factorize(A));
    EXPECT_GT(lu.rcond(), 0.0);
    const VecX b = A * x;
    EXPECT_LT((A * lu.solve(b) - b).norm(), 1e-12 * A.norm() * x.norm());  // backward error
    EXPECT_LT((lu.inverse() * A - MatX::Identity(n, n)).norm(), 1e-8);
    const VecX bt = A.transpose() * x;
    EXPECT_LT((A.transpose() * lu.solveTransposed(bt) - bt).norm(), 1e-12 * A.norm() * x.norm());
  }
}

TEST(DenseLu, ThePivotGateSkipsOnlyTheEstimatesOfUnspreadPivots) {
  // estimateConditionOnlyIfPivotsSpread: pivots within 1e6 of each other are accepted without
  // dgecon (rcond() is then the pivot ratio, 1/cond(U) <= it); wider ones are
  // estimated and judged by the threshold as without the gate.
  DenseLuSolver gated, plain;
  gated.estimateConditionOnlyIfPivotsSpread(true);
  const MatX A = 4.0 * MatX::Identity(8, 8) + randomMatrix(8, 41);
  ASSERT_TRUE(gated.factorize(A));
  ASSERT_TRUE(plain.factorize(A));
  EXPECT_GE(gated.rcond(), DenseLuSolver::kEstimatePivotRatio);
  const VecX b = randomVector(8, 42);
  EXPECT_LT((A * gated.solve(b) - b).norm(), 1e-12 * b.norm());
  for (double small : {1e-9, 1e-17}) {  // spread pivots: estimated, refused below 1e-15
    MatX D = MatX::Identity(4, 4);
    D(2, 2) = small;
    EXPECT_EQ(gated.factorize(D), plain.factorize(D)) << small;
    EXPECT_EQ(gated.factorize(D), small > 1e-15) << small;
    EXPECT_NEAR(gated.rcond(), plain.rcond(), 1e-6 * plain.rcond()) << small;
  }
  MatX singular = randomMatrix(6, 43);
  singular.row(4) = 2.0 * singular.row(1);
  EXPECT_FALSE(gated.factorize(singular));
}

TEST(DenseLu, RefusesSingularAndNonFiniteMatrices) {
  MatX A = randomMatrix(6, 11);
  A.row(4) = 2.0 * A.row(1);
  DenseLuSolver lu;
  EXPECT_FALSE(lu.factorize(A));
  A = randomMatrix(6, 12);
  A(2, 3) = std::nan("");
  EXPECT_FALSE(lu.factorize(A));
  // A NaN or an infinity in a column of small entries, before or after the largest column:
  // refused whatever the order in which the column norms are compared
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()})
    for (int col : {0, 3, 5}) {
      A = randomMatrix(6, 13);
      A *= 1e-6;
      A.col(2) *= 1e12;
      A(4, col) = bad;
      EXPECT_FALSE(lu.factorize(A)) << bad << " in column " << col;
      EXPECT_FALSE(lu.factorize(MatX(A))) << bad << " in column " << col << ", in place";
    }
  A = MatX::Identity(3, 3);
  A(2, 2) = 1e-18;  // rcond 1e-18 below the default threshold 1e-15
  EXPECT_FALSE(lu.factorize(A));
  EXPECT_TRUE(lu.factorize(A, 1e-20));
}

// A banded sparse Jacobian (diagonally dominant, not symmetric) with `fixed` DOFs pinned.
SparseMatrix bandedJacobian(int n, const std::vector<bool>& fixed, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  TripletList t;
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - 4); j <= std::min(n - 1, i + 4); ++j) {
      if (fixed[i] || fixed[j]) {
        if (i == j) t.emplace_back(i, i, 1.0);
        continue;
      }
      t.emplace_back(i, j, i == j ? 12.0 + u(rng) : u(rng));
    }
  SparseMatrix S(n, n);
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

struct InverseTerm {
  std::vector<int> dofs;
  MatX matrix;
  LuFactoredMatrix factored;
  VecX weights;
  double scale;
};

// A non-symmetric, well-conditioned matrix of scale 1e-2 on shuffled DOFs (like Ablk, in m).
InverseTerm inverseTerm(int n, int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  std::shuffle(all.begin(), all.end(), rng);
  InverseTerm term{{all.begin(), all.begin() + m}, {}, {}, {}, -50.0};
  term.matrix = 1e-2 * (MatX::Identity(m, m) * 4.0 + 0.3 * randomMatrix(m, seed + 1));
  std::uniform_real_distribution<double> u(0.5, 2.0);
  term.weights = VecX::NullaryExpr(m, [&] { return u(rng); });
  EXPECT_TRUE(term.factored.factorize(term.matrix));
  return term;
}

// J = S - sum scale * block - sum scale * diag(w) A^{-1}, fixed DOFs pinned, formed explicitly.
MatX explicitJacobian(const SparseMatrix& S, const std::vector<const InverseTerm*>& terms,
                      const std::vector<int>& dense_dofs, const MatX& dense_block,
                      const std::vector<bool>& fixed) {
  MatX J(S);
  auto subtract = [&J](const std::vector<int>& dofs, const MatX& block) {
    for (size_t r = 0; r < dofs.size(); ++r)
      for (size_t c = 0; c < dofs.size(); ++c) J(dofs[r], dofs[c]) -= block(r, c);
  };
  if (!dense_dofs.empty()) subtract(dense_dofs, dense_block);
  for (const InverseTerm* t : terms)
    subtract(t->dofs, t->scale * t->weights.asDiagonal() * t->matrix.inverse());
  for (size_t i = 0; i < fixed.size(); ++i)
    if (fixed[i]) {
      J.row(i).setZero();
      J.col(i).setZero();
      J(i, i) = 1.0;
    }
  return J;
}

struct Case {
  std::vector<int> fixed;  ///< pinned DOFs (-1 entries: the first DOF of the inverse block)
  bool dense_block;
  bool second_inverse;
  bool expect_preconditioned;
};

TEST(DenseNewtonSystem, MatchesTheExplicitJacobianWithoutFormingTheInverse) {
  const int n = 60, m = 24;
  const std::vector<Case> cases = {{{}, false, false, true},
                                   {{}, true, false, true},
                                   {{}, false, true, true},
                                   {{-1}, false, false, false}};
  for (size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE("case " + std::to_string(k));
    const Case& c = cases[k];
    const InverseTerm first = inverseTerm(n, m, 40 + k);
    const InverseTerm second = inverseTerm(n, 10, 50 + k);
    std::vector<bool> fixed(n, false);
    for (int i = 0; i < n; ++i)  // two pinned DOFs outside the first block
      if (std::find(first.dofs.begin(), first.dofs.end(), i) == first.dofs.end() &&
          std::count(fixed.begin(), fixed.end(), true) < 2)
        fixed[i] = true;
    for (int f : c.fixed) fixed[f < 0 ? first.dofs[0] : f] = true;
    const SparseMatrix S = bandedJacobian(n, fixed, 7 + k);
    const std::vector<int> dense_dofs = c.dense_block ? second.dofs : std::vector<int>{};
    const MatX dense_block = 3.0 * randomMatrix(static_cast<int>(second.dofs.size()), 60 + k);
    std::vector<const InverseTerm*> terms{&first};
    if (c.second_inverse) terms.push_back(&second);

    DenseNewtonSystem system;
    system.begin(S, fixed);
    if (c.dense_block) system.addDense(dense_dofs, dense_block, 1.0);
    for (const InverseTerm* t : terms)
      system.addScaledInverse(t->dofs, t->factored, t->weights, t->scale);
    ASSERT_TRUE(system.factorize(1e-15));
    EXPECT_EQ(system.preconditioned(), c.expect_preconditioned);
    // condensed whenever preconditioned without other dense blocks (the second inverse block is
    // added as a dense block)
    EXPECT_EQ(system.condensed(), c.expect_preconditioned && !c.dense_block && !c.second_inverse);

    const MatX J = explicitJacobian(S, terms, dense_dofs, dense_block, fixed);
    std::mt19937 rng(90 + k);
    std::normal_distribution<double> g;
    VecX rhs = VecX::NullaryExpr(n, [&] { return g(rng); });
    for (int i = 0; i < n; ++i)
      if (fixed[i]) rhs(i) = 0.0;
    const VecX dq = system.solve(rhs);
    EXPECT_LT((J * dq - rhs).norm(), 1e-11 * J.norm() * dq.norm());  // backward error
    const VecX reference = J.partialPivLu().solve(rhs);
    EXPECT_LT((dq - reference).norm(), 1e-9 * reference.norm());
    for (int i = 0; i < n; ++i) {
      if (fixed[i]) {
        EXPECT_EQ(dq(i), 0.0);
      }
    }
  }
}

// The matrix CondensedDenseLu sees: sparse columns from S, dense columns on `dofs`.
MatX withDenseColumns(const SparseMatrix& S, const std::vector<int>& dofs,
                      const CondensedDenseLu::RowMajorMatX& columns) {
  MatX M(S);
  for (size_t k = 0; k < dofs.size(); ++k) M.col(dofs[k]) = columns.col(k);
  return M;
}

TEST(CondensedDenseLu, SolvesLikeADenseLuOfTheWholeMatrix) {
  const int n = 70, m = 30;
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::vector<int> all(n);
    for (int i = 0; i < n; ++i) all[i] = i;
    std::shuffle(all.begin(), all.end(), rng);
    const std::vector<int> dofs(all.begin(), all.begin() + m);  // unsorted, like a node list
    std::vector<bool> fixed(n, false);
    fixed[all[m]] = fixed[all[m + 1]] = true;  // two pinned sparse DOFs
    const SparseMatrix S = bandedJacobian(n, fixed, 20 + seed);
    CondensedDenseLu::RowMajorMatX columns = randomMatrix(n, 40 + seed).leftCols(m);
    for (int k = 0; k < m; ++k) columns(dofs[k], k) += 15.0;  // a dominant diagonal
    for (int i = 0; i < n; ++i)
      if (fixed[i]) columns.row(i).setZero();
    const MatX M = withDenseColumns(S, dofs, columns);

    CondensedDenseLu lu;
    for (int repeat = 0; repeat < 2; ++repeat) {  // the second reuses the symbolic analysis
      ASSERT_TRUE(lu.factorize(S, dofs, columns, 1e-15));
      std::normal_distribution<double> g;
      const VecX rhs = VecX::NullaryExpr(n, [&] { return g(rng); });
      VecX x = rhs;
      lu.solveInPlace(x);
      EXPECT_LT((M * x - rhs).norm(), 1e-12 * M.norm() * x.norm());  // backward error
      const VecX reference = M.partialPivLu().solve(rhs);
      EXPECT_LT((x - reference).norm(), 1e-10 * reference.norm());
      columns *= 1.5;  // new values, same pattern
      const MatX scaled = withDenseColumns(S, dofs, columns);
      ASSERT_TRUE(lu.factorize(S, dofs, columns, 1e-15));
      VecX y = rhs;
      lu.solveInPlace(y);
      EXPECT_LT((scaled * y - rhs).norm(), 1e-12 * scaled.norm() * y.norm());
      columns /= 1.5;
    }
  }
}

TEST(CondensedDenseLu, RefusesASingularSparseBlockAndTheNewtonSystemFactorsTheWhole) {
  // The sparse DOFs' block is singular (two equal rows) while the whole matrix is not: the
  // condensation has no pivoting across blocks and must refuse; DenseNewtonSystem then factors
  // the whole matrix and still solves it.
  const int n = 12, m = 6;
  const std::vector<int> dofs{0, 1, 2, 3, 4, 5};
  TripletList t;
  for (int i = m; i < n; ++i) t.emplace_back(i, i, i == n - 1 ? 0.0 : 3.0);  // S block singular
  for (int i = 0; i < m; ++i) t.emplace_back(n - 1, i, 0.0);
  t.emplace_back(0, n - 1, 1.0);  // column n-1 lives on a dense DOF's row only
  SparseMatrix S(n, n);
  S.setFromTriplets(t.begin(), t.end());
  CondensedDenseLu::RowMajorMatX columns = randomMatrix(n, 5).leftCols(m);
  columns.row(n - 1).setConstant(1.0);  // row n-1 lives on the dense columns only
  const MatX M = withDenseColumns(S, dofs, columns);
  ASSERT_GT(std::abs(M.determinant()), 1e-8);
  CondensedDenseLu lu;
  EXPECT_FALSE(lu.factorize(S, dofs, columns, 1e-15));

  // The same structure through the Newton system: J = S - s diag(w) A^{-1} on dofs.
  InverseTerm term{dofs, MatX::Identity(m, m) + 0.2 * randomMatrix(m, 6), {}, VecX::Ones(m), 1.0};
  ASSERT_TRUE(term.factored.factorize(term.matrix));
  SparseMatrix S2 = S;
  for (int i = 0; i < m; ++i) S2.coeffRef(n - 1, i) = 1.0 + i;  // row n-1 couples to the dofs
  const std::vector<bool> fixed(n, false);
  DenseNewtonSystem system;
  system.begin(S2, fixed);
  system.addScaledInverse(term.dofs, term.factored, term.weights, term.scale);
  ASSERT_TRUE(system.factorize(1e-15));
  EXPECT_TRUE(system.preconditioned());
  EXPECT_FALSE(system.condensed());
  const MatX J = explicitJacobian(S2, {&term}, {}, MatX(), fixed);
  const VecX rhs = VecX::LinSpaced(n, -1.0, 1.0);
  const VecX dq = system.solve(rhs);
  EXPECT_LT((J * dq - rhs).norm(), 1e-11 * J.norm() * dq.norm());
}

TEST(DenseNewtonSystem, DefaultSinkFormsTheSameBlock) {
  // The interface default (used by sinks that only take dense blocks) adds diag(w) A^{-1}.
  struct Capture : DenseJacobianSink {
    MatX J = MatX::Zero(60, 60);
    void addDense(const std::vector<int>& dofs, const MatX& block, double scale) override {
      for (size_t r = 0; r < dofs.size(); ++r)
        for (size_t c = 0; c < dofs.size(); ++c) J(dofs[r], dofs[c]) += scale * block(r, c);
    }
  } capture;
  const InverseTerm t = inverseTerm(60, 24, 70);
  capture.addScaledInverse(t.dofs, t.factored, t.weights, t.scale);
  const MatX expected = -explicitJacobian(SparseMatrix(60, 60), {&t}, {}, MatX(), {});
  EXPECT_LT((capture.J - expected).norm(), 1e-10 * expected.norm());
}

}  // namespace
}  // namespace flagella
