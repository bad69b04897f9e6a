#include "flagella_sim/solver/dense_newton_system.h"

#include <stdexcept>

#include "flagella_sim/core/blas.h"

namespace flagella {

void DenseNewtonSystem::begin(const SparseMatrix& sparse, const std::vector<bool>& fixed) {
  sparse_ = &sparse;
  fixed_ = &fixed;
  formed_ = false;  // the dense matrix is formed only when needed (formDense)
  has_dense_blocks_ = false;
  has_inverse_ = false;
  preconditioned_ = false;
  condensed_ = false;
  completed_ = false;
}

void DenseNewtonSystem::formDense() {
  if (formed_) return;
  jacobian_ = *sparse_;  // reuses the last LU's storage when the size is unchanged
  formed_ = true;
}

void DenseNewtonSystem::addDense(const std::vector<int>& dofs, const MatX& block, double scale) {
  formDense();
  const int n = static_cast<int>(dofs.size());
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) jacobian_(dofs[r], dofs[c]) -= scale * block(r, c);
  has_dense_blocks_ = true;
}

void DenseNewtonSystem::addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a,
                                         const VecX& row_weights, double scale) {
  InverseBlock block{dofs, &a, row_weights, scale};
  if (has_inverse_) {  // only one block can precondition the system
    subtractExplicitInverse(block);
    return;
  }
  inverse_ = std::move(block);
  has_inverse_ = true;
}

void DenseNewtonSystem::subtractExplicitInverse(const InverseBlock& block) {
  addDense(block.dofs, block.row_weights.asDiagonal() * block.matrix->inverse(), block.scale);
}

bool DenseNewtonSystem::canPrecondition() const {
  for (int dof : inverse_.dofs)
    if ((*fixed_)[dof]) return false;  // a pinned DOF would mix with free ones through A
  return inverse_.matrix->matrix().diagonal().cwiseAbs().mean() > 0.0;
}

void DenseNewtonSystem::precondition() {
  // docs/model.md 4.4: J C = J0 C - (s / alpha) P^T diag(w) P, J0 C = J0 + J0 P^T (A / alpha - I) P
  const MatX& a = inverse_.matrix->matrix();
  const std::vector<int>& dofs = inverse_.dofs;
  const int m = static_cast<int>(dofs.size());
  const int n = static_cast<int>(sparse_->rows());
  alpha_ = a.diagonal().cwiseAbs().mean();
  // J0 P^T A / alpha, row by row: each nonzero J0(i, d_k) adds J0(i, d_k) A(k, :) / alpha to row i
  // (BLAS axpy on contiguous rows, vectorised for the CPU at run time)
  a_rows_ = a / alpha_;  // C's block, A / alpha
  RowMajorMatX& columns = columns_;
  columns.setZero(n, m);
  const int one = 1;
  for (int k = 0; k < m; ++k) {
    auto add = [&](int row, double value) {
      daxpy_(&m, &value, a_rows_.row(k).data(), &one, columns.row(row).data(), &one);
    };
    if (has_dense_blocks_) {
      for (int row = 0; row < n; ++row)
        if (jacobian_(row, dofs[k]) != 0.0) add(row, jacobian_(row, dofs[k]));
    } else {
      for (SparseMatrix::InnerIterator it(*sparse_, dofs[k]); it; ++it)
        add(static_cast<int>(it.row()), it.value());
    }
  }
  for (int k = 0; k < m; ++k)
    columns(dofs[k], k) -= inverse_.scale * inverse_.row_weights(k) / alpha_;
  for (int i = 0; i < n; ++i)
    if ((*fixed_)[i]) columns.row(i).setZero();  // Dirichlet rows (docs/model.md 1.10)
  preconditioned_ = true;
}

bool DenseNewtonSystem::factorize(double min_rcond) {
  if (completed_) throw std::logic_error("DenseNewtonSystem: one factorize() per begin()");
  completed_ = true;
  if (has_inverse_ && canPrecondition()) {
    precondition();
    // Only the preconditioned columns are dense: condense the others out (docs/model.md 4.4)
    condensed_ = condense_ && !has_dense_blocks_ &&
                 condensed_lu_.factorize(*sparse_, inverse_.dofs, columns_, min_rcond);
    if (condensed_) return true;
    formDense();
    for (size_t k = 0; k < inverse_.dofs.size(); ++k)
      jacobian_.col(inverse_.dofs[k]) = columns_.col(k);
  } else if (has_inverse_) {
    subtractExplicitInverse(inverse_);
  }
  formDense();
  // Dirichlet DOFs (docs/model.md 1.10)
  for (int i = 0; i < static_cast<int>(fixed_->size()); ++i) {
    if (!(*fixed_)[i]) continue;
    jacobian_.row(i).setZero();
    jacobian_.col(i).setZero();
    jacobian_(i, i) = 1.0;
  }
  // J is not needed after its LU: factored in place, its storage comes back for the next begin()
  const bool factored = lu_.factorize(std::move(jacobian_), min_rcond);
  formed_ = false;
  return factored;
}

VecX DenseNewtonSystem::solve(const VecX& rhs) const {
  VecX z, dq;
  solveUnmapped(rhs, z);
  map(z, dq);
  return dq;
}

void DenseNewtonSystem::solveUnmapped(const VecX& rhs, VecX& z) const {
  if (condensed_) {
    z = rhs;
    condensed_lu_.solveInPlace(z);
  } else {
    z = lu_.solve(rhs);
  }
}

void DenseNewtonSystem::map(const VecX& z, VecX& dq) const {
  dq = z;
  if (!preconditioned_) return;
  const std::vector<int>& dofs = inverse_.dofs;
  gathered_.resize(dofs.size());
  for (size_t k = 0; k < dofs.size(); ++k) gathered_(k) = z(dofs[k]);
  // dq = C z, C with the block's matrix now (docs/model.md 4.4): within the step of factorize()
  // that is the matrix factored, so dq = J^{-1} rhs; in a later step the kept factorisation is a
  // preconditioner of the current J C, whose product then needs no solve with A (Newton-Krylov)
  const VecX mapped = inverse_.matrix->multiply(gathered_) / alpha_;
  for (size_t k = 0; k < dofs.size(); ++k) dq(dofs[k]) = mapped(k);
}

}  // namespace flagella
