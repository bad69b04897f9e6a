#include "flagella_sim/solver/sparse_lu_solver.h"

#include <suitesparse/klu.h>

#include <stdexcept>

namespace flagella {

struct SparseLuSolver::Impl {
  klu_common common;
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  int n = 0;
};

SparseLuSolver::SparseLuSolver() : impl_(new Impl) {
  klu_defaults(&impl_->common);
  // No row scaling: measured 9% faster on the robots with identical results; the pivot
  // order is still chosen by partial pivoting on the first factorisation and re-chosen
  // whenever the reciprocal condition estimate degrades.
  impl_->common.scale = -1;
}

SparseLuSolver::~SparseLuSolver() {
  freeNumeric();
  if (impl_->symbolic) klu_free_symbolic(&impl_->symbolic, &impl_->common);
  delete impl_;
}

void SparseLuSolver::freeNumeric() {
  if (impl_->numeric) klu_free_numeric(&impl_->numeric, &impl_->common);
  impl_->numeric = nullptr;
}

void SparseLuSolver::analyze(const SparseMatrix& A) {
  freeNumeric();
  if (impl_->symbolic) klu_free_symbolic(&impl_->symbolic, &impl_->common);
  impl_->n = static_cast<int>(A.rows());
  impl_->symbolic = klu_analyze(impl_->n, const_cast<int*>(A.outerIndexPtr()),
                                const_cast<int*>(A.innerIndexPtr()), &impl_->common);
  if (!impl_->symbolic) throw std::runtime_error("KLU symbolic analysis failed");
}

bool SparseLuSolver::factorize(const SparseMatrix& A) {
  if (!impl_->symbolic) analyze(A);
  int* Ap = const_cast<int*>(A.outerIndexPtr());
  int* Ai = const_cast<int*>(A.innerIndexPtr());
  double* Ax = const_cast<double*>(A.valuePtr());
  if (impl_->numeric) {
    if (klu_refactor(Ap, Ai, Ax, impl_->symbolic, impl_->numeric, &impl_->common) &&
        pivotRatio() > kMinPivotRatio) {
      ++refactorizations_;
      return true;
    }
    freeNumeric();
  }
  impl_->numeric = klu_factor(Ap, Ai, Ax, impl_->symbolic, &impl_->common);
  ++full_factorizations_;
  return impl_->numeric != nullptr && impl_->common.status == KLU_OK;
}

VecX SparseLuSolver::solve(const VecX& b) {
  VecX x = b;
  if (!solveInPlace(x.data(), impl_->n, 1)) x.setConstant(std::numeric_limits<double>::quiet_NaN());
  return x;
}

bool SparseLuSolver::solveInPlace(double* b, int ldim, int nrhs) {
  return impl_->numeric &&
         klu_solve(impl_->symbolic, impl_->numeric, ldim, nrhs, b, &impl_->common);
}

double SparseLuSolver::pivotRatio() {
  if (!impl_->numeric || !klu_rcond(impl_->symbolic, impl_->numeric, &impl_->common)) return 0.0;
  return impl_->common.rcond;
}

}  // namespace flagella
