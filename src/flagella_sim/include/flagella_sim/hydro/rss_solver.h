// RSS solve for a polyline (docs/model.md 4.3-4.4): factors Ablk once with partial-pivot LU (Ablk
// is not symmetric, so Cholesky/LDLT would be wrong) and maps nodal velocities to forces. With
// setLazyFactorization(true) Ablk is factored only when a solve first needs it (a Newton solve
// that follows its iterates by their preimages needs none, docs/model.md 4.4).
#pragma once

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/core/factored_matrix.h"
#include "flagella_sim/hydro/rss_matrix.h"

namespace flagella::rss {

class RssSolver : public FactoredMatrix {
 public:
  /// Validates (see validatePolyline; viscosity finite and > 0), assembles and factors Ablk.
  RssSolver(const Polyline& nodes, double eps, double viscosity);
  /// The same for several chains sharing one system (segments name node pairs).
  RssSolver(const Polyline& nodes, const Segments& segments, double eps, double viscosity);
  /// Rebuilds and refactors for new nodes (the storage is reused when the size is unchanged).
  /// Throws as the constructor; the solver is then unusable until an update succeeds. Lazy: the
  /// factorisation waits for the first solve, which throws instead if Ablk is singular.
  void update(const Polyline& nodes, const Segments& segments, double eps, double viscosity);
  /// Rigid reuse (docs/model.md 4.4): when `nodes` are a rigid motion of the polyline last
  /// built, to within `tolerance` eps at every node after the best-fit rotation R (Kabsch),
  /// with the same segments and eps, the factored matrix serves rotated, Ablk(R y + c) =
  /// Q Ablk(y) Q^T with Q = diag(R, ..., R) (the regularized Stokeslet is isotropic); otherwise
  /// as update(). The Voronoi lengths and viscosity are always the new ones. Returns true when
  /// the factorisation was reused. tolerance 0: always update().
  bool updateOrReuse(const Polyline& nodes, const Segments& segments, double eps, double viscosity,
                     double tolerance);

  int nodeCount() const { return static_cast<int>(lengths_.size()); }
  /// Ablk at the current nodes (formed from the factored one when it was reused rotated).
  const MatX& matrix() const override;
  /// Ablk^{-1} b at the current nodes (FactoredMatrix).
  VecX solveWith(const VecX& b) const override { return solveCurrent(b); }
  /// Ablk v at the current nodes: Q Ablk(y) Q^T v when reused rotated (no rotated copy formed).
  VecX multiply(const VecX& v) const override;
  /// Ablk^{-1} at the current nodes: Q Ablk(y)^{-1} Q^T.
  MatX inverse() const override;
  const VecX& voronoiLengths() const { return lengths_; }
  double eps() const { return eps_; }
  double viscosity() const { return mu_; }

  /// F = 8 pi mu Ablk^{-1} U: force densities on the fluid (3M, N/m) from nodal velocities U (3M).
  VecX forceDensities(const VecX& velocities) const;
  /// F_p^hyd = -l_p f_p: hydrodynamic forces on the nodes (docs/model.md 4.3).
  VecX nodalForces(const VecX& velocities) const;
  /// K = 8 pi mu D Ablk^{-1}, D = diag(l_p I3), so that F^hyd = -K U (docs/model.md 4.4 option B).
  /// Forms the inverse (O(M^3)): for checks; the Newton solve never needs it.
  MatX dragMatrix() const;
  /// The row weights 8 pi mu l_p of K = diag(weights) Ablk^{-1} (3M entries).
  VecX dragRowWeights() const;
  /// The largest node distance from the rigid motion of the factored polyline at the last
  /// updateOrReuse() [m] (0 after a rebuild).
  double lastDeviation() const { return deviation_; }
  /// Factor Ablk only when a solve needs it (default off: update() factors at once).
  void setLazyFactorization(bool on) { lazy_ = on; }

 private:
  void checkSize(const VecX& velocities) const;
  /// Ablk^{-1} v at the current nodes: Q Ablk(y)^{-1} Q^T v (Q = I unless reused rotated).
  VecX solveCurrent(const VecX& v) const;
  /// m -> Q m Q^T for a 3M x 3M matrix m (Q = diag(R, ..., R)).
  void rotateBlocks(MatX& m) const;
  /// Q v, or Q^T v when `inverse` (Q = diag(R, ..., R), R the reuse's rotation).
  VecX rotateEachNode(VecX v, bool inverse) const;
  /// Factors Ablk(y) if not yet done; throws std::invalid_argument if it is singular.
  void ensureFactored() const;

  double eps_ = 0.0, mu_ = 0.0;
  MatX ablk_;  ///< Ablk(y) of the factored polyline y
  VecX lengths_;
  mutable DenseLuSolver lu_;
  mutable bool factored_ = false;  ///< lu_ holds Ablk(y)
  bool lazy_ = false;
  Polyline factored_nodes_;  ///< y, the polyline Ablk was last built at
  Segments segments_;
  bool rotated_ = false;
  Mat3 rotation_ = Mat3::Identity();  ///< R: current nodes = R y + c (+ deviation)
  double deviation_ = 0.0;
  mutable MatX rotated_matrix_;  ///< Q Ablk(y) Q^T, formed when matrix() asks
  mutable bool rotated_matrix_valid_ = false;
};

}  // namespace flagella::rss
