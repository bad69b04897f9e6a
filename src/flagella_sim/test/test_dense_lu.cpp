// The dense LU (LAPACK) used for RSS and dense Newton systems: solves and inverts non-symmetric
// matrices (residual checks), refuses singular or non-finite ones. The dense Newton system with an
// inverse block solved without the inverse (right preconditioning) against the explicitly formed
// Jacobian, with and without Dirichlet DOFs, dense blocks and a second inverse block.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/solver/dense_newton_system.h"
#include "support/random_matrices.h"

namespace flagella {
namespace {

using testing::randomMatrix;

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
