// The product J v of a Newton Jacobian with dense blocks (docs/model.md 4.4) without forming J:
// J = S - sum_b s_b P_b^T B_b P_b - sum_i s_i P_i^T diag(w_i) A_i^{-1} P_i, S sparse with its
// Dirichlet DOFs pinned, the dense blocks acting between free DOFs only (the Dirichlet rows and
// columns of J are those of the identity). Each inverse block costs one solve with A_i's
// factorisation per product, except at a vector mapped by A_i (applyMapped). For the
// Newton-Krylov update (solver.krylov_iterations).
#pragma once

#include <vector>

#include "flagella_sim/effects/effect.h"

namespace flagella {

class DenseJacobianProduct : public DenseJacobianSink {
 public:
  /// Starts from the sparse part and the mask of Dirichlet DOFs; both, and every matrix handed
  /// to addScaledInverse, must stay unchanged while apply() is used.
  void begin(const SparseMatrix& sparse, const std::vector<bool>& fixed);
  void addDense(const std::vector<int>& dofs, const MatX& block, double scale) override;
  void addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a,
                        const VecX& row_weights, double scale) override;
  /// out = J v.
  void apply(const VecX& v, VecX& out) const;
  /// out = J v for v = C z, where C maps z by `mapped` (v = z except A z / alpha on the DOFs of
  /// the inverse block of A = mapped, DenseNewtonSystem::map): that block's product is then
  /// diag(w) z / alpha, with no solve (docs/model.md 4.4).
  void applyMapped(const VecX& v, const VecX& z, const FactoredMatrix* mapped, double alpha,
                   VecX& out) const;

 private:
  struct Block {
    std::vector<int> dofs;
    MatX dense;                               ///< B (dense blocks)
    const FactoredMatrix* inverse = nullptr;  ///< A (inverse blocks)
    VecX row_weights;
    double scale = 0.0;
  };
  Block& nextBlock(const std::vector<int>& dofs, double scale);

  const SparseMatrix* sparse_ = nullptr;
  const std::vector<bool>* fixed_ = nullptr;
  std::vector<Block> blocks_;  ///< storage kept between begin() calls
  int block_count_ = 0;
  mutable VecX gathered_, block_product_;
};

}  // namespace flagella
