// Tails (or a flagellum) denser than the robot's config says by an extra density drho: each tail
// edge of rest length l and radius r carries the extra weight drho pi r^2 l g, half at each of
// its end nodes (docs/model.md 5.1). Zero Jacobian (constant vectors).
#pragma once

#include <array>
#include <vector>

#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/effect_descriptor.h"

namespace flagella {

/// The registry entry (effect_list.def).
const EffectDescriptor& tailWeightEffect();

class TailWeight : public Effect, public ForceLaw {
 public:
  static constexpr const char* kName = "tail_weight";
  TailWeight();
  void attach(const RodNetwork& net) override;
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override;

 private:
  int extra_density_ = 0;
  /// Per tail edge: its two end nodes and its volume pi r^2 l at rest [m^3].
  struct EdgeVolume {
    std::array<int, 2> nodes;
    double volume = 0.0;
  };
  std::vector<EdgeVolume> edges_;
};

}  // namespace flagella
