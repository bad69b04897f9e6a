// Rigid helix of regularized Stokeslet segments and its axial resistance coefficients
// (docs/model.md 4.5 for the eps rule; helix geometry as docs/model.md 8.4.1; coefficients A, B, D
// as in Rodenborn et al., PNAS 110 (2013) E338).
#pragma once

#include <optional>

#include "flagella_sim/hydro/rss_matrix.h"

namespace flagella::rss {

/// sqrt(e): eps = sqrt(e) a makes a line of regularized Stokeslets reproduce the local
/// slender-body operator of a filament of radius a (docs/model.md 4.5; Keller & Rubinow 1976).
inline constexpr double kSqrtE = 1.6487212707001282;
/// Default edge length in filament radii (chosen from the convergence check in test_rss.cpp).
inline constexpr double kDefaultEdgeLengthInRadii = 2.0;
/// Largest node count the dense solve accepts (memory ~ 2 * (3M)^2 doubles).
inline constexpr int kMaxHelixNodes = 2000;

struct HelixSpec {
  double helix_radius = 0;            // R > 0 [m]
  double pitch = 0;                   // lambda > 0 [m]
  double axial_length = 0;            // L > 0 [m]
  double filament_radius = 0;         // a: 0 < a < R and 2 a < lambda [m]
  std::optional<double> eps;          // regularization; default sqrt(e) a
  std::optional<double> edge_length;  // target edge length; default kDefaultEdgeLengthInRadii a
  int handedness = +1;                // +1 right-handed, -1 left-handed
};

/// The values actually used after defaults (eps, edge length) are filled in.
struct ResolvedHelix {
  HelixSpec spec;          // eps and edge_length always set
  double arc_length = 0;   // (L/lambda) sqrt((2 pi R)^2 + lambda^2)
  double actual_edge = 0;  // chord length of the equal edges (<= edge_length)
  int node_count = 0;
};

/// Validates (throws std::invalid_argument naming the field and range) and fills defaults.
ResolvedHelix resolveHelix(const HelixSpec& spec);

/// Nodes x(phi) = (R cos phi, chi R sin phi, lambda phi / 2 pi), phi in [0, 2 pi L / lambda],
/// equal arc-length edges (docs/model.md 8.4.1 parametrisation with axis z).
Polyline helixNodes(const ResolvedHelix& helix);

/// Axial resistance of the rigid helix (axis z through the origin) in a fluid of viscosity mu.
/// Loads are those the helix exerts on the fluid (minus the hydrodynamic loads on the helix):
///   F_z = A U + B Omega,  T_z = B_reciprocal U + D Omega
/// for translation speed U along +z and rotation rate Omega about +z. A, D > 0. B < 0 for a
/// right-handed helix (it screws forward along +z when Omega > 0), B > 0 for a left-handed one.
/// Reciprocity makes B_reciprocal = B up to discretisation error.
struct HelixResistance {
  ResolvedHelix helix;
  double viscosity = 1;
  double A = 0, B = 0, B_reciprocal = 0, D = 0;  // dimensional: N s/m, N s, N m s
  double dimensionlessA() const;                 // A / (mu R)
  double dimensionlessB() const;                 // B / (mu R^2) (signed)
  double dimensionlessD() const;                 // D / (mu R^3)
};

HelixResistance helixResistance(const HelixSpec& spec, double viscosity);

}  // namespace flagella::rss
