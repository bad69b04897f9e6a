// Right-preconditioned GMRES (Saad & Schultz 1986, SIAM J. Sci. Stat. Comput. 7: 856; Saad 2003,
// "Iterative Methods for Sparse Linear Systems", Alg. 9.5): solves A x = b from x = 0 by
// minimising |b - A M^{-1} y| over the Krylov space of A M^{-1}, x = M^{-1} y, with modified
// Gram-Schmidt and Givens rotations, no restart. Storage is kept between solves (no allocation
// once the size and iteration cap are unchanged).
#pragma once

#include <cmath>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

struct GmresResult {
  int iterations = 0;          ///< products with A (and M^{-1}) taken
  double residual_norm = 0.0;  ///< |b - A x| (2-norm), as the recurrence gives it
  bool converged = false;      ///< residual_norm <= the tolerance
};

class Gmres {
 public:
  /// x with |b - A x| <= tolerance (2-norm) in at most max_iterations products. `apply(v, out)`
  /// sets out = A v and `precondition(v, out)` out = M^{-1} v (out has the size of v).
  template <class Apply, class Precondition>
  GmresResult solve(const Apply& apply, const Precondition& precondition, const VecX& b,
                    double tolerance, int max_iterations, VecX& x);

 private:
  void reserve(int n, int m);

  std::vector<VecX> basis_;  ///< v_0 .. v_m (orthonormal)
  MatX hessenberg_;          ///< (m + 1) x m, rotated to upper triangular as it grows
  VecX cosines_, sines_, g_;
  VecX work_, preconditioned_;
};

inline void Gmres::reserve(int n, int m) {
  if (static_cast<int>(basis_.size()) < m + 1) basis_.resize(m + 1);
  for (VecX& v : basis_)
    if (v.size() != n) v.resize(n);
  if (hessenberg_.rows() != m + 1 || hessenberg_.cols() != m) hessenberg_.resize(m + 1, m);
  cosines_.resize(m);
  sines_.resize(m);
  g_.resize(m + 1);
  work_.resize(n);
  preconditioned_.resize(n);
}

template <class Apply, class Precondition>
GmresResult Gmres::solve(const Apply& apply, const Precondition& precondition, const VecX& b,
                         double tolerance, int max_iterations, VecX& x) {
  const int n = static_cast<int>(b.size());
  const int m = std::max(1, max_iterations);
  reserve(n, m);
  x.setZero(n);
  GmresResult result;
  const double beta = b.norm();
  result.residual_norm = beta;
  if (!(beta > tolerance)) {
    result.converged = std::isfinite(beta);
    return result;
  }
  basis_[0] = b / beta;
  g_.setZero();
  g_(0) = beta;
  int k = 0;
  while (k < m) {
    precondition(basis_[k], preconditioned_);
    apply(preconditioned_, work_);
    for (int i = 0; i <= k; ++i) {  // modified Gram-Schmidt
      hessenberg_(i, k) = basis_[i].dot(work_);
      work_ -= hessenberg_(i, k) * basis_[i];
    }
    const double h_next = work_.norm();
    for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
      const double a = hessenberg_(i, k), c = hessenberg_(i + 1, k);
      hessenberg_(i, k) = cosines_(i) * a + sines_(i) * c;
      hessenberg_(i + 1, k) = -sines_(i) * a + cosines_(i) * c;
    }
    const double diagonal = hessenberg_(k, k);
    const double r = std::hypot(diagonal, h_next);
    if (!(r > 0.0) || !std::isfinite(r)) break;  // no new direction (or non-finite): stop here
    cosines_(k) = diagonal / r;
    sines_(k) = h_next / r;
    hessenberg_(k, k) = r;
    g_(k + 1) = -sines_(k) * g_(k);
    g_(k) = cosines_(k) * g_(k);
    ++k;
    result.residual_norm = std::abs(g_(k));
    if (result.residual_norm <= tolerance || !(h_next > 0.0)) break;
    basis_[k] = work_ / h_next;
  }
  result.iterations = k;
  if (k == 0) return result;
  // y from the triangular system, x = M^{-1} (V y)
  VecX y = hessenberg_.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g_.head(k));
  work_.setZero();
  for (int i = 0; i < k; ++i) work_ += y(i) * basis_[i];
  precondition(work_, x);
  result.converged = result.residual_norm <= tolerance && x.allFinite();
  return result;
}

}  // namespace flagella
