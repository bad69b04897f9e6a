#include "flagella_sim/solver/dense_jacobian_product.h"

namespace flagella {

void DenseJacobianProduct::begin(const SparseMatrix& sparse, const std::vector<bool>& fixed) {
  sparse_ = &sparse;
  fixed_ = &fixed;
  block_count_ = 0;
}

DenseJacobianProduct::Block& DenseJacobianProduct::nextBlock(const std::vector<int>& dofs,
                                                             double scale) {
  if (block_count_ == static_cast<int>(blocks_.size())) blocks_.emplace_back();
  Block& b = blocks_[block_count_++];
  b.dofs = dofs;  // capacity reused
  b.scale = scale;
  b.inverse = nullptr;
  return b;
}

void DenseJacobianProduct::addDense(const std::vector<int>& dofs, const MatX& block, double scale) {
  nextBlock(dofs, scale).dense = block;
}

void DenseJacobianProduct::addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a,
                                            const VecX& row_weights, double scale) {
  Block& b = nextBlock(dofs, scale);
  b.inverse = &a;
  b.row_weights = row_weights;
}

void DenseJacobianProduct::apply(const VecX& v, VecX& out) const {
  applyMapped(v, v, nullptr, 1.0, out);
}

void DenseJacobianProduct::applyMapped(const VecX& v, const VecX& z, const FactoredMatrix* mapped,
                                       double alpha, VecX& out) const {
  out.noalias() = *sparse_ * v;  // pinned rows and columns: identity already
  const std::vector<bool>& fixed = *fixed_;
  for (int k = 0; k < block_count_; ++k) {
    const Block& b = blocks_[k];
    const int m = static_cast<int>(b.dofs.size());
    const bool by_preimage = b.inverse && b.inverse == mapped;
    const VecX& source = by_preimage ? z : v;
    gathered_.resize(m);
    for (int i = 0; i < m; ++i) gathered_(i) = fixed[b.dofs[i]] ? 0.0 : source(b.dofs[i]);
    if (by_preimage)  // docs/model.md 4.4: diag(w) A^{-1} (A z / alpha) = diag(w) z / alpha
      block_product_ = b.row_weights.cwiseProduct(gathered_) / alpha;
    else if (b.inverse)  // docs/model.md 4.4: diag(w) A^{-1} v
      block_product_ = b.row_weights.cwiseProduct(b.inverse->solveWith(gathered_));
    else
      block_product_.noalias() = b.dense * gathered_;
    for (int i = 0; i < m; ++i)
      if (!fixed[b.dofs[i]]) out(b.dofs[i]) -= b.scale * block_product_(i);
  }
}

}  // namespace flagella
