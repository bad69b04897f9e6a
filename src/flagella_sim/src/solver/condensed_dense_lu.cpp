#include "flagella_sim/solver/condensed_dense_lu.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "flagella_sim/core/blas.h"
#include "flagella_sim/solver/sparse_lu_solver.h"

namespace flagella {

CondensedDenseLu::CondensedDenseLu() : ss_lu_(std::make_unique<SparseLuSolver>()) {
  schur_lu_.estimateConditionOnlyIfPivotsSpread(true);  // once per Newton factorisation
}
CondensedDenseLu::~CondensedDenseLu() = default;

void CondensedDenseLu::partition(int n, const std::vector<int>& dense_dofs) {
  if (dense_dofs == dense_ && static_cast<int>(slot_.size()) == n) return;
  dense_ = dense_dofs;
  slot_.assign(n, 0);
  for (int d : dense_) {
    if (d < 0 || d >= n || slot_[d] != 0)
      throw std::invalid_argument("CondensedDenseLu: dense DOFs must be distinct and in range");
    slot_[d] = 1;
  }
  sparse_.clear();
  for (int i = 0; i < n; ++i)
    if (slot_[i] == 0) sparse_.push_back(i);
  for (size_t k = 0; k < dense_.size(); ++k) slot_[dense_[k]] = static_cast<int>(k);
  for (size_t k = 0; k < sparse_.size(); ++k) slot_[sparse_[k]] = -1 - static_cast<int>(k);
  ss_.resize(0, 0);  // a new symbolic analysis
}

bool CondensedDenseLu::gatherSparseBlocks(const SparseMatrix& sparse) {
  const int ns = static_cast<int>(sparse_.size()), nh = static_cast<int>(dense_.size());
  TripletList ss, hs;
  for (int c = 0; c < ns; ++c) {
    bool diagonal = false;
    for (SparseMatrix::InnerIterator it(sparse, sparse_[c]); it; ++it) {
      const int s = slot_[it.row()];
      if (s < 0) {
        ss.emplace_back(-1 - s, c, it.value());
        diagonal = diagonal || -1 - s == c;
      } else if (it.value() != 0.0) {
        hs.emplace_back(s, c, it.value());
      }
    }
    if (!diagonal) ss.emplace_back(c, c, 0.0);  // structural diagonal (pivots may need it)
  }
  SparseMatrix new_ss(ns, ns);
  new_ss.setFromTriplets(ss.begin(), ss.end());
  hs_.resize(nh, ns);
  hs_.setFromTriplets(hs.begin(), hs.end());
  const bool changed =
      ss_.rows() != ns || ss_.nonZeros() != new_ss.nonZeros() ||
      !std::equal(new_ss.outerIndexPtr(), new_ss.outerIndexPtr() + ns + 1, ss_.outerIndexPtr()) ||
      !std::equal(new_ss.innerIndexPtr(), new_ss.innerIndexPtr() + new_ss.nonZeros(),
                  ss_.innerIndexPtr());
  ss_ = std::move(new_ss);
  return changed;
}

bool CondensedDenseLu::factorize(const SparseMatrix& sparse, const std::vector<int>& dense_dofs,
                                 const RowMajorMatX& dense_columns, double min_rcond) {
  const int n = static_cast<int>(sparse.rows());
  if (sparse.cols() != n || dense_columns.rows() != n ||
      dense_columns.cols() != static_cast<Eigen::Index>(dense_dofs.size()))
    throw std::invalid_argument("CondensedDenseLu: sizes of the sparse and dense columns differ");
  partition(n, dense_dofs);
  if (sparse_.empty()) return false;
  if (gatherSparseBlocks(sparse)) ss_lu_->analyze(ss_);
  if (!ss_lu_->factorize(ss_) || !(ss_lu_->pivotRatio() > min_rcond)) return false;
  const int nh = static_cast<int>(dense_.size()), ns = static_cast<int>(sparse_.size());
  // X = M_SS^{-1} M_SH
  x_ = dense_columns(sparse_, Eigen::all);
  if (!ss_lu_->solveInPlace(x_.data(), ns, nh) || !x_.allFinite()) return false;
  x_rows_ = x_;
  // Complement C = M_HH - M_HS X, row by row: each nonzero M_HS(h, s) takes M_HS(h, s) X(s, :)
  // from row h (BLAS axpy on contiguous memory), kept as C^T so that a row of C is a column.
  schur_t_ = dense_columns(dense_, Eigen::all).transpose();
  const int one = 1;
  for (int s = 0; s < ns; ++s)
    for (SparseMatrix::InnerIterator it(hs_, s); it; ++it) {
      const double minus = -it.value();
      daxpy_(&nh, &minus, x_rows_.row(s).data(), &one, schur_t_.col(it.row()).data(), &one);
    }
  // LU of C^T (its 1-norm condition estimate is C's in the infinity norm)
  return schur_lu_.factorize(std::move(schur_t_), min_rcond);
}

void CondensedDenseLu::solveInPlace(VecX& rhs) const {
  // y = M_SS^{-1} r_S; z_H = C^{-1} (r_H - M_HS y); z_S = y - X z_H
  ws_ = rhs(sparse_);
  if (!ss_lu_->solveInPlace(ws_.data(), static_cast<int>(ws_.size()), 1)) {
    rhs.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  wh_ = rhs(dense_);
  wh_.noalias() -= hs_ * ws_;
  wh_ = schur_lu_.solveTransposed(wh_);
  ws_.noalias() -= x_ * wh_;
  rhs(sparse_) = ws_;
  rhs(dense_) = wh_;
}

}  // namespace flagella
