// The uni-flagellar helical robot of docs/model.md 8.4: rigid head (x_0, x_1, x_2) with the motor
// at x_1, a rigid radial plate x_2 -> x_3, an axial hook x_3 -> x_4 and a helix x_4 .. x_{N-1}
// coaxial with the head axis (+z). Untethered (8.4.1) or held by a gimbal at x_0 (8.4.2).
#pragma once

#include <vector>

#include "flagella_sim/rod/network_builder.h"

namespace flagella {

enum class HelicalMount { kUntethered, kGimbal };

/// Helix handedness chi of docs/model.md 8.4.1.
inline constexpr int kRightHanded = +1;
inline constexpr int kLeftHanded = -1;
/// Allowed number of pitches L_t / lambda.
inline constexpr double kMinPitchCount = 0.5;
inline constexpr double kMaxPitchCount = 50.0;

/// Geometry and material of the helical robot; defaults are docs/model.md 8.4.1's (VPS Shore 32
/// flagellum, r0 = 1.584 mm from the gimbal sweep).
struct HelicalGeometry {
  double head_radius = 0.018;   ///< R_H: |e^0| = |e^1| [m]
  double helix_radius = 0.018;  ///< R_t: helix radius and plate length |e^2| [m]
  double pitch = 0.036;         ///< lambda [m]
  double pitch_count = 3.5;     ///< L_t / lambda
  double hook_length = 0.0188;  ///< L_h = |e^3|, along the axis [m]
  double edge_length = 5e-3;    ///< target helix edge length Dl [m]
  /// chi: +1 right-handed, -1 left-handed (the group's code). With omega_T > 0 (flagellum
  /// turning about +z) a left-handed helix pushes the robot head first (toward -z).
  int handedness = kLeftHanded;
  HelicalMount mount = HelicalMount::kUntethered;
  double rigid_factor = 1e3;  ///< stiffness multiplier of head, shaft, plate (docs/model.md 1.4)
  /// Multiplier of the hook's bending-twisting spring (e^3, e^4) at x_4 against the
  /// flagellum's EI, GJ: a hook stiffer or softer than the filament (docs/model.md 8.4.1).
  double hook_stiffness_scale = 1.0;
  RodMaterial flagellum{1.225e6, 0.5, 1.584e-3, 1240.0};  ///< E, nu, r0, rho

  double axialLength() const { return pitch_count * pitch; }  ///< L_t [m]
  double arcLength() const;                                   ///< L_arc [m]
  int helixEdges() const;  ///< max(2, round(L_arc / Dl)): edges from x_4 to the tip
  double edgesPerTurn() const { return helixEdges() / pitch_count; }
  /// Helix point x(phi) of docs/model.md 8.4.1; x(0) = x_4.
  Vec3 helixPoint(double phi) const;
};

/// Throws ConfigError naming the field (robot.<field>) and its allowed range, or the reason for a
/// self-intersecting helix.
void validateHelicalGeometry(const HelicalGeometry& geometry);

/// Builds the network of docs/model.md 8.4.1 (and fixes x_0 and theta^0 for the gimbal, 8.4.2).
/// parts.tail_nodes holds one chain {x_3, x_4, ..., x_{N-1}} (hook included), tail_edges
/// {e^3, e^4, ...}.
RodNetwork buildHelicalRobot(const HelicalGeometry& geometry);

/// The helix nodes x_4 .. x_{N-1} of a network built by buildHelicalRobot.
std::vector<int> helixNodes(const RobotParts& parts);

}  // namespace flagella
