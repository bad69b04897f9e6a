// RSS solve for a polyline (docs/model.md 4.3-4.4): factors Ablk once with partial-pivot LU (Ablk
// is not symmetric, so Cholesky/LDLT would be wrong) and maps nodal velocities to forces.
#pragma once

#include "flagella_sim/core/dense_lu_solver.h"
#include "flagella_sim/hydro/rss_matrix.h"

namespace flagella::rss {

class RssSolver {
 public:
  /// Validates (see validatePolyline; viscosity finite and > 0), assembles and factors Ablk.
  RssSolver(const Polyline& nodes, double eps, double viscosity);
  /// The same for several chains sharing one system (segments name node pairs).
  RssSolver(const Polyline& nodes, const Segments& segments, double eps, double viscosity);
  /// Rebuilds and refactors for new nodes (the storage is reused when the size is unchanged).
  /// Throws as the constructor; the solver is then unusable until an update succeeds.
  void update(const Polyline& nodes, const Segments& segments, double eps, double viscosity);

  int nodeCount() const { return static_cast<int>(lengths_.size()); }
  const MatX& matrix() const { return ablk_; }
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
  /// The LU factorisation of Ablk.
  const DenseLuSolver& factorisation() const { return lu_; }

 private:
  void checkSize(const VecX& velocities) const;

  double eps_ = 0.0, mu_ = 0.0;
  MatX ablk_;
  VecX lengths_;
  DenseLuSolver lu_;
};

}  // namespace flagella::rss
