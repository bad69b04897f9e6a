// The Newton system J dq = r of a step whose Jacobian has dense blocks (docs/model.md 4.4 option
// B): J = S - sum_b s_b P_b^T B_b P_b - s P^T diag(w) A^{-1} P, with S the sparse part (Dirichlet
// DOFs pinned) and P selecting DOFs. The block given through its matrix A (the RSS drag, A = Ablk)
// is never inverted: the system is right-preconditioned by A on its DOFs (docs/model.md 4.4),
//   (J C) z = r,  dq = C z,  C = identity except A / alpha on those DOFs,
// and J C = S C - (s / alpha) P^T diag(w) P needs only the sparse-times-dense product S P^T A.
// Falls back to forming A^{-1} when a Dirichlet DOF is among the block's DOFs or a second such
// block is added.
// The preconditioned system is factored by condensing the sparse DOFs out (CondensedDenseLu, a
// Schur complement on the block's DOFs), or as a whole when that refuses or is switched off.
#pragma once

#include <vector>

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/effects/effect.h"
#include "flagella_sim/solver/condensed_dense_lu.h"

namespace flagella {

class DenseNewtonSystem : public DenseJacobianSink {
 public:
  /// Starts a Jacobian from its sparse part (fixed DOFs already pinned in it) and the mask of
  /// Dirichlet DOFs; both must stay unchanged until solve() is done with them.
  void begin(const SparseMatrix& sparse, const std::vector<bool>& fixed);
  /// J -= scale * block at rows and columns `dofs` (dF/dq += scale * block).
  void addDense(const std::vector<int>& dofs, const MatX& block, double scale) override;
  /// J -= scale * diag(row_weights) * matrix^{-1}; `matrix` must stay unchanged until
  /// factorize() and alive while solve() is used (its mapping reads the matrix's current value).
  void addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a,
                        const VecX& row_weights, double scale) override;
  /// Completes J (pins the Dirichlet DOFs) and factors it in place with partial-pivot LU, once
  /// per begin(); false if it is singular (reciprocal condition estimate below `min_rcond`).
  bool factorize(double min_rcond);
  /// The Newton update dq with J dq = rhs (J as at the last factorize(); valid until the next
  /// begin()). Preconditioned: dq = C z with C mapping by the block's matrix as it is now (the
  /// matrix at factorize() within the step; a later step's when the factorisation is kept as
  /// a preconditioner, docs/model.md 4.4).
  VecX solve(const VecX& rhs) const;
  /// z = (J C)^{-1} rhs, the update before the mapping dq = C z (z = dq when not preconditioned).
  void solveUnmapped(const VecX& rhs, VecX& z) const;
  /// dq = C z: z with the block's DOFs replaced by A z / alpha, A the block's matrix now.
  void map(const VecX& z, VecX& dq) const;
  /// The matrix whose block the last factorize() preconditioned (null when not preconditioned),
  /// and alpha of its mapping C.
  const FactoredMatrix* mappingMatrix() const {
    return preconditioned_ ? inverse_.matrix : nullptr;
  }
  double mappingScale() const { return alpha_; }
  /// True when the last factorize() used the preconditioned form (no inverse formed).
  bool preconditioned() const { return preconditioned_; }
  /// Factor a preconditioned system without other dense blocks by condensing out its sparse DOFs
  /// (CondensedDenseLu; the whole matrix when that refuses). Default on.
  void setCondensation(bool on) { condense_ = on; }
  /// True when the last factorize() condensed the sparse DOFs out.
  bool condensed() const { return condensed_; }

 private:
  struct InverseBlock {
    std::vector<int> dofs;
    const FactoredMatrix* matrix = nullptr;
    VecX row_weights;
    double scale = 0.0;
  };
  bool canPrecondition() const;
  void subtractExplicitInverse(const InverseBlock& block);
  /// The preconditioned columns J C P^T (columns_), Dirichlet rows zeroed.
  void precondition();
  /// The dense matrix from the sparse part, once per begin().
  void formDense();

  using RowMajorMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  const SparseMatrix* sparse_ = nullptr;
  const std::vector<bool>* fixed_ = nullptr;
  MatX jacobian_;
  bool formed_ = false;  ///< jacobian_ holds this begin()'s matrix
  bool has_dense_blocks_ = false;
  bool has_inverse_ = false;
  InverseBlock inverse_;
  bool preconditioned_ = false;
  bool completed_ = false;
  double alpha_ = 1.0;  ///< mean |diagonal| of the preconditioning matrix
  DenseLuSolver lu_;
  bool condense_ = true;
  bool condensed_ = false;
  CondensedDenseLu condensed_lu_;
  RowMajorMatX a_rows_;    ///< A / alpha as preconditioned at the last factorize()
  mutable VecX gathered_;  ///< z on the block's DOFs (map())
  RowMajorMatX columns_;   ///< J C on the preconditioned DOFs (n x m), from precondition()
};

}  // namespace flagella
