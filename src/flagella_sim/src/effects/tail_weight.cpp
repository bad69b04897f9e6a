#include "flagella_sim/effects/tail_weight.h"

#include <cmath>

namespace flagella {

TailWeight::TailWeight() : Effect(kName, tailWeightEffect().parameters) {
  extra_density_ = parameterIndex("extra_density");
}

const EffectDescriptor& tailWeightEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = TailWeight::kName;
    e.description = "tails denser (or lighter) than the config says: their extra weight";
    e.parameters = {{"extra_density", 0.0, -1e4, 1e4, "kg/m^3",
                     "tail material density minus robot.density, drho (negative: lighter)"}};
    e.make = [](const EffectBuildContext&) { return std::make_unique<TailWeight>(); };
    DiscoveryHints h;
    h.title = "tails denser or lighter than modelled (their extra weight)";
    h.signature =
        "sinking and pitch: the track descends or climbs and the head axis tilts as "
        "the flagellum's extra weight or buoyancy pulls its far end";
    h.needs = kVertical | kTimeResolved;
    h.variables = {{"extra_density", "extra_density", false, "kg/m^3", -200.0, 200.0, false, 0.0}};
    h.starts = {{-2.0}, {2.0}};
    // a silicone casting 0.1-0.3 % off the glycerin's density: the helical robot's track then
    // sinks or climbs by millimetres within 40 s (docs/model.md 7.6)
    h.typical = {{"extra_density", 1.0, 4.0, true}};
    h.steady_table_data = false;
    // docs/model.md 7.6: tried on swimmers in a liquid, whose flagellum the Stokeslets model
    h.requires_effect = "rss";
    h.requires_what = "a flagellum swimming in a liquid (the regularized Stokeslets)";
    e.discovery = h;
    return e;
  }();
  return d;
}

void TailWeight::attach(const RodNetwork& net) {
  edges_.clear();
  for (const std::vector<int>& tail : net.parts.tail_edges)
    for (const int j : tail) {
      const double r = net.edge_radius[j];
      edges_.push_back(
          {{net.edges[j].start_node, net.edges[j].end_node}, M_PI * r * r * net.rest_lengths[j]});
    }
}

void TailWeight::addForce(const EffectContext& ctx, VecX& force, JacobianSink* /*jacobian*/) const {
  // docs/model.md 5.1: drho pi r^2 l g per tail edge, half at each end node
  const double drho = params_[extra_density_];
  for (const EdgeVolume& e : edges_) {
    const Vec3 half = 0.5 * drho * e.volume * ctx.medium.gravity;
    force.segment<3>(3 * e.nodes[0]) += half;
    force.segment<3>(3 * e.nodes[1]) += half;
  }
}

}  // namespace flagella
