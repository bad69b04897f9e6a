#include "flagella_sim/core/dense_lu_solver.h"

#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

extern "C" {
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info);
void dgetri_(const int* n, double* a, const int* lda, const int* ipiv, double* work,
             const int* lwork, int* info);
void dgecon_(const char* norm, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info);
void openblas_set_num_threads(int num_threads);
}

namespace flagella {

namespace {
// One thread per solve: runs are parallelised across simulations (sweeps), not inside a solve.
void useOneThread() {
  static std::once_flag once;
  std::call_once(once, [] { openblas_set_num_threads(1); });
}
}  // namespace

bool DenseLuSolver::factorize(const MatX& A, double min_rcond) {
  if (!checkInput(A)) return false;
  lu_ = A;  // reuses the storage when the size is unchanged
  return factorizeStored(min_rcond);
}

bool DenseLuSolver::factorize(MatX&& A, double min_rcond) {
  if (!checkInput(A)) return false;
  lu_.swap(A);  // A keeps the previous factorisation's storage for its owner to reuse
  return factorizeStored(min_rcond);
}

bool DenseLuSolver::checkInput(const MatX& A) {
  useOneThread();
  if (A.rows() != A.cols()) throw std::invalid_argument("DenseLuSolver: matrix is not square");
  rcond_ = 0.0;
  // 1-norm, for the condition estimate, in the same pass as the finiteness check: a NaN or an
  // infinite entry makes its column's sum non-finite (a finite matrix whose sum overflows would
  // have a zero condition estimate, refused all the same)
  anorm_ = A.cwiseAbs().colwise().sum().maxCoeff<Eigen::PropagateNaN>();
  return std::isfinite(anorm_);
}

bool DenseLuSolver::factorizeStored(double min_rcond) {
  const int n = static_cast<int>(lu_.rows());
  pivots_.assign(n, 0);
  int info = 0;
  dgetrf_(&n, &n, lu_.data(), &n, pivots_.data(), &info);
  if (info != 0) return false;
  if (pivot_gate_ && n > 0) {
    const auto pivots = lu_.diagonal().cwiseAbs();
    const double ratio = pivots.minCoeff() / pivots.maxCoeff();
    if (ratio >= kEstimatePivotRatio) {  // 1 / ratio <= cond(U): no spread, no estimate
      rcond_ = ratio;
      return ratio > min_rcond;
    }
  }
  work_.resize(4 * n);
  iwork_.resize(n);
  const char norm = '1';
  dgecon_(&norm, &n, lu_.data(), &n, &anorm_, &rcond_, work_.data(), iwork_.data(), &info);
  return info == 0 && rcond_ > min_rcond;
}

VecX DenseLuSolver::solve(const VecX& b) const { return solveWith('N', b); }

VecX DenseLuSolver::solveTransposed(const VecX& b) const { return solveWith('T', b); }

VecX DenseLuSolver::solveWith(char trans, const VecX& b) const {
  const int n = size(), nrhs = 1;
  VecX x = b;
  int info = 0;
  dgetrs_(&trans, &n, &nrhs, lu_.data(), &n, pivots_.data(), x.data(), &n, &info);
  if (info != 0) x.setConstant(std::numeric_limits<double>::quiet_NaN());
  return x;
}

MatX DenseLuSolver::inverse() const {
  const int n = size();
  MatX inv = lu_;
  int info = 0, lwork = -1;
  double query = 0.0;
  dgetri_(&n, inv.data(), &n, pivots_.data(), &query, &lwork, &info);
  lwork = static_cast<int>(query);
  std::vector<double> work(std::max(1, lwork));
  dgetri_(&n, inv.data(), &n, pivots_.data(), work.data(), &lwork, &info);
  if (info != 0) inv.setConstant(std::numeric_limits<double>::quiet_NaN());
  return inv;
}

}  // namespace flagella
