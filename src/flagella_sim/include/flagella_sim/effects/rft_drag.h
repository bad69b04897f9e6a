// Resistive force theory on the tail nodes, granular or viscous (docs/model.md 2), with the exact
// Jacobian (velocity and geometric parts) and an optional per-node viscosity from the
// interface profile (docs/model.md 3.3).
#pragma once

#include <vector>

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"
#include "flagella_sim/effects/rft_coefficients.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& rftDragEffect();

class RftDrag : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "rft";
  explicit RftDrag(RftLogForm form, bool use_interface_profile = false);
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

  RftLogForm logForm() const { return form_; }

 private:
  struct TailNode {
    int node = -1;
    int prev = -1;                         ///< previous node along the tail, -1 at the root
    int next = -1;                         ///< next node along the tail, -1 at the tip
    int edge_in = -1, edge_out = -1;       ///< edges prev-node and node-next (-1 if none)
    double sign_in = 1.0, sign_out = 1.0;  ///< +1 when that edge is stored in that direction
    double voronoi_length = 0.0;
    double tail_length = 0.0;
    double tail_radius = 0.0;
  };
  /// Drag coefficients of a tail at the medium's viscosity (cached: the log is not free).
  RftCoefficients coefficients(const TailNode& n, double viscosity) const;
  RftLogForm form_;
  bool use_profile_;
  int drag_scale_ = 0;
  std::vector<TailNode> nodes_;
  mutable double cached_viscosity_ = -1.0;
  mutable std::vector<RftCoefficients> cached_;  // per node
};

}  // namespace flagella
