// GMRES (solver/gmres.h) against direct solves, and the matrix-free product of a Newton Jacobian
// with an inverse block (solver/dense_jacobian_product.h) against the Jacobian formed explicitly.
#include <gtest/gtest.h>

#include <random>

#include "flagella_sim/core/factored_matrix.h"
#include "flagella_sim/solver/dense_jacobian_product.h"
#include "flagella_sim/solver/dense_newton_system.h"
#include "flagella_sim/solver/gmres.h"
#include "support/random_matrices.h"

namespace flagella {
namespace {

using testing::randomMatrix;

using testing::randomVector;

TEST(Gmres, WithoutPreconditionerReachesTheExactSolutionInAtMostNProducts) {
  const int n = 25;
  const MatX A = 5.0 * MatX::Identity(n, n) + randomMatrix(n, 1);  // not symmetric
  const VecX b = randomVector(n, 2);
  Gmres gmres;
  VecX x;
  const auto apply = [&](const VecX& v, VecX& out) { out = A * v; };
  const auto identity = [](const VecX& v, VecX& out) { out = v; };
  const GmresResult r = gmres.solve(apply, identity, b, 1e-12 * b.norm(), n, x);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.iterations, n);
  EXPECT_LT((A * x - b).norm(), 1e-11 * b.norm());
  EXPECT_NEAR(r.residual_norm, (A * x - b).norm(), 1e-10 * b.norm());  // the recurrence is true
}

TEST(Gmres, AnExactPreconditionerTakesOneProductAndANearbyOneFew) {
  const int n = 60;
  const MatX A = 8.0 * MatX::Identity(n, n) + randomMatrix(n, 3);
  const VecX b = randomVector(n, 4);
  const auto apply = [&](const VecX& v, VecX& out) { out = A * v; };
  Gmres gmres;
  VecX x;
  const Eigen::PartialPivLU<MatX> exact(A);
  const GmresResult one = gmres.solve(
      apply, [&](const VecX& v, VecX& out) { out = exact.solve(v); }, b, 1e-10 * b.norm(), 20, x);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_LT((A * x - b).norm(), 1e-9 * b.norm());
  // A lagged preconditioner: A changed by a rank-2 term. GMRES converges in about rank + 1.
  MatX lagged = A;
  lagged += 0.5 * randomVector(n, 5) * randomVector(n, 6).transpose();
  lagged += 0.5 * randomVector(n, 7) * randomVector(n, 8).transpose();
  const Eigen::PartialPivLU<MatX> old(lagged);
  const GmresResult few = gmres.solve(
      apply, [&](const VecX& v, VecX& out) { out = old.solve(v); }, b, 1e-10 * b.norm(), 20, x);
  EXPECT_TRUE(few.converged);
  EXPECT_LE(few.iterations, 4);
  EXPECT_LT((A * x - b).norm(), 1e-9 * b.norm());
}

TEST(Gmres, ReportsAShortfallWithinTheCapAndAZeroRightHandSide) {
  const int n = 40;
  const MatX A = MatX::Identity(n, n) + 3.0 * randomMatrix(n, 9);  // badly conditioned for GMRES
  const VecX b = randomVector(n, 10);
  Gmres gmres;
  VecX x;
  const auto apply = [&](const VecX& v, VecX& out) { out = A * v; };
  const auto identity = [](const VecX& v, VecX& out) { out = v; };
  const GmresResult capped = gmres.solve(apply, identity, b, 1e-12 * b.norm(), 3, x);
  EXPECT_FALSE(capped.converged);
  EXPECT_EQ(capped.iterations, 3);
  EXPECT_NEAR(capped.residual_norm, (A * x - b).norm(), 1e-10 * b.norm());
  EXPECT_LT(capped.residual_norm, b.norm());  // the minimal residual never grows
  const GmresResult zero = gmres.solve(apply, identity, VecX::Zero(n), 1e-12, 3, x);
  EXPECT_TRUE(zero.converged);
  EXPECT_EQ(zero.iterations, 0);
  EXPECT_EQ(x.norm(), 0.0);
}

TEST(DenseJacobianProduct, EqualsTheJacobianFormedExplicitly) {
  // J = S - s1 B - s2 diag(w) A^{-1}, with Dirichlet DOFs pinned (identity rows and columns).
  const int n = 30;
  std::vector<bool> fixed(n, false);
  fixed[3] = fixed[11] = true;
  MatX dense_S = MatX::Zero(n, n);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - 3); j <= std::min(n - 1, i + 3); ++j)
      dense_S(i, j) = fixed[i] || fixed[j] ? (i == j ? 1.0 : 0.0) : (i == j ? 6.0 : u(rng));
  const SparseMatrix S = dense_S.sparseView();
  const std::vector<int> block_dofs = {0, 5, 11, 20};         // 11 is pinned
  const std::vector<int> inverse_dofs = {2, 3, 7, 8, 9, 25};  // 3 is pinned
  const MatX B = randomMatrix(4, 12);
  LuFactoredMatrix A;
  ASSERT_TRUE(A.factorize(4.0 * MatX::Identity(6, 6) + randomMatrix(6, 13)));
  const VecX w = VecX::LinSpaced(6, 0.5, 2.0);
  DenseJacobianProduct product;
  product.begin(S, fixed);
  product.addDense(block_dofs, B, 0.7);
  product.addScaledInverse(inverse_dofs, A, w, -1.3);

  MatX J = dense_S;
  const MatX K = w.asDiagonal() * A.matrix().inverse();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (!fixed[block_dofs[r]] && !fixed[block_dofs[c]])
        J(block_dofs[r], block_dofs[c]) -= 0.7 * B(r, c);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      if (!fixed[inverse_dofs[r]] && !fixed[inverse_dofs[c]])
        J(inverse_dofs[r], inverse_dofs[c]) += 1.3 * K(r, c);
  const VecX v = randomVector(n, 14);
  VecX out;
  product.apply(v, out);
  EXPECT_LT((out - J * v).norm(), 1e-12 * (J * v).norm());
  EXPECT_EQ(out(3), v(3));  // pinned rows are the identity's
}

// A banded matrix (bandwidth 2) with `diagonal` on its diagonal and uniform(-1, 1) beside it.
MatX bandedMatrix(int n, double diagonal, unsigned seed) {
  MatX m = MatX::Zero(n, n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - 2); j <= std::min(n - 1, i + 2); ++j)
      m(i, j) = i == j ? diagonal : u(rng);
  return m;
}

// z with its entries at `dofs` replaced by A z_dofs / alpha (DenseNewtonSystem::map).
VecX mappedBy(const MatX& a, const std::vector<int>& dofs, const VecX& z, double alpha) {
  VecX z_h(dofs.size());
  for (size_t k = 0; k < dofs.size(); ++k) z_h(k) = z(dofs[k]);
  const VecX mapped = a * z_h / alpha;
  VecX v = z;
  for (size_t k = 0; k < dofs.size(); ++k) v(dofs[k]) = mapped(k);
  return v;
}

TEST(DenseJacobianProduct, AtAMappedVectorTakesTheInverseBlockFromThePreimage) {
  // v = C z (v = z except A z_H / alpha on the inverse block's DOFs H): J v formed explicitly
  // against the product from z, which needs no solve with A (docs/model.md 4.4).
  const int n = 24;
  const std::vector<bool> fixed(n, false);
  const MatX dense_S = bandedMatrix(n, 5.0, 21);
  const SparseMatrix S = dense_S.sparseView();
  const std::vector<int> dofs = {1, 4, 5, 9, 10, 17, 22};
  const int m = static_cast<int>(dofs.size());
  LuFactoredMatrix A;
  ASSERT_TRUE(A.factorize(3.0 * MatX::Identity(m, m) + randomMatrix(m, 22)));
  const VecX w = VecX::LinSpaced(m, 0.7, 1.9);
  DenseJacobianProduct product;
  product.begin(S, fixed);
  product.addScaledInverse(dofs, A, w, -2.1);
  const double alpha = 2.7;
  const VecX z = randomVector(n, 23);
  const VecX v = mappedBy(A.matrix(), dofs, z, alpha);
  MatX J = dense_S;
  const MatX K = w.asDiagonal() * A.matrix().inverse();
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) J(dofs[r], dofs[c]) += 2.1 * K(r, c);
  VecX out;
  product.applyMapped(v, z, &A, alpha, out);
  EXPECT_LT((out - J * v).norm(), 1e-12 * (J * v).norm());
  LuFactoredMatrix other;  // another matrix's mapping: the block is solved as in apply()
  ASSERT_TRUE(other.factorize(MatX::Identity(m, m)));
  product.applyMapped(v, VecX::Zero(n), &other, alpha, out);
  EXPECT_LT((out - J * v).norm(), 1e-12 * (J * v).norm());
}

TEST(DenseNewtonSystem, TheMappedUpdateSolvesTheJacobianAndFollowsTheMatrixAsItIsNow) {
  // J = S - s diag(w) A^{-1}, solved by (J C) z = r, dq = C z; C maps by A's current value.
  const int n = 20;
  const std::vector<bool> fixed(n, false);
  const MatX dense_S = bandedMatrix(n, 6.0, 31);
  const SparseMatrix S = dense_S.sparseView();
  const std::vector<int> dofs = {2, 3, 4, 11, 12, 13};
  const int m = static_cast<int>(dofs.size());
  LuFactoredMatrix A;
  ASSERT_TRUE(A.factorize(4.0 * MatX::Identity(m, m) + randomMatrix(m, 32)));
  const VecX w = VecX::LinSpaced(m, 1.0, 2.0);
  DenseNewtonSystem system;
  system.setCondensation(false);
  system.begin(S, fixed);
  system.addScaledInverse(dofs, A, w, -1.5);
  ASSERT_TRUE(system.factorize(1e-15));
  ASSERT_EQ(system.mappingMatrix(), &A);
  MatX J = dense_S;
  const MatX K = w.asDiagonal() * A.matrix().inverse();
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) J(dofs[r], dofs[c]) += 1.5 * K(r, c);
  const VecX r = randomVector(n, 33);
  VecX z, dq;
  system.solveUnmapped(r, z);
  system.map(z, dq);
  EXPECT_LT((J * dq - r).norm(), 1e-11 * r.norm());
  EXPECT_LT((system.solve(r) - dq).norm(), 1e-14 * dq.norm());
  // A later value of A: the mapping uses it (the factorisation is then a preconditioner only)
  ASSERT_TRUE(A.factorize(5.0 * MatX::Identity(m, m) + randomMatrix(m, 34)));
  system.map(z, dq);
  const VecX expected = mappedBy(A.matrix(), dofs, z, system.mappingScale());
  EXPECT_LT((dq - expected).norm(), 1e-14 * expected.norm());
}

}  // namespace
}  // namespace flagella
