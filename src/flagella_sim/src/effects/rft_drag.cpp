#include "flagella_sim/effects/rft_drag.h"

namespace flagella {

RftDrag::RftDrag(RftLogForm form, bool use_interface_profile)
    : Effect(kName, rftDragEffect().parameters), form_(form), use_profile_(use_interface_profile) {
  drag_scale_ = parameterIndex("drag_scale");
}

const EffectDescriptor& rftDragEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = RftDrag::kName;
    e.description = "resistive force theory on the tails, granular or viscous";
    e.options = {
        {"log_form", "2L/r0", {"2L/r0", "L/r0"}, "logarithm of the RFT coefficients"},
        {"use_interface_profile", "false", {}, "per-node viscosity from medium.interface_profile"}};
    e.parameters = {{"drag_scale", 1.0, 0.0, 1e3, "", "multiplier on both RFT drag coefficients"}};
    e.make = [](const EffectBuildContext& c) {
      return std::make_unique<RftDrag>(parseRftLogForm(c.spec.option("log_form")),
                                       c.spec.flag("use_interface_profile"));
    };
    return e;
  }();
  return d;
}

void RftDrag::attach(const RodNetwork& net) {
  nodes_.clear();
  cached_viscosity_ = -1.0;
  for (size_t k = 0; k < net.parts.tail_nodes.size(); ++k) {
    const std::vector<int>& tail = net.parts.tail_nodes[k];
    const std::vector<int>& edges = net.parts.tail_edges[k];
    double length = 0.0;
    for (int e : edges) length += net.rest_lengths[e];
    const double radius = net.edge_radius[edges.front()];
    for (size_t i = 0; i < tail.size(); ++i) {
      // docs/model.md 2 [ASSUMED]: the root node (disc rim) gets half the first tail edge
      const double before = i > 0 ? net.rest_lengths[edges[i - 1]] : 0.0;
      const double after = i + 1 < tail.size() ? net.rest_lengths[edges[i]] : 0.0;
      nodes_.push_back({tail[i], i > 0 ? tail[i - 1] : -1, i + 1 < tail.size() ? tail[i + 1] : -1,
                        0.5 * (before + after), length, radius});
    }
  }
}

RftCoefficients RftDrag::coefficients(const TailNode& n, double viscosity) const {
  if (viscosity != cached_viscosity_) {
    cached_.clear();
    for (const TailNode& m : nodes_)
      cached_.push_back(rftCoefficients(viscosity, m.tail_length, m.tail_radius, form_));
    cached_viscosity_ = viscosity;
  }
  return cached_[&n - nodes_.data()];
}

void RftDrag::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  const Mat3 I = Mat3::Identity();
  for (const TailNode& n : nodes_) {
    const Vec3 x = nodePosition(ctx.q, n.node);
    // docs/model.md 2: node tangent s = (t^{j-1} + t^j)/2 normalised; single edge at the ends
    // [CORR-4]
    Vec3 s = Vec3::Zero();
    Vec3 t_in = Vec3::Zero(), t_out = Vec3::Zero();
    double len_in = 0.0, len_out = 0.0;
    int edge_count = 0;
    if (n.prev >= 0) {
      const Vec3 e = x - nodePosition(ctx.q, n.prev);
      len_in = e.norm();
      t_in = e / len_in;
      s += t_in;
      ++edge_count;
    }
    if (n.next >= 0) {
      const Vec3 e = nodePosition(ctx.q, n.next) - x;
      len_out = e.norm();
      t_out = e / len_out;
      s += t_out;
      ++edge_count;
    }
    s /= edge_count;
    const double s_norm = s.norm();
    const Vec3 that = s / s_norm;
    const RftCoefficients c = coefficients(n, ctx.viscosity);
    const double height = x.dot(ctx.medium.up);
    const double mu_factor = use_profile_ ? ctx.medium.profile.factor(height) : 1.0;
    const double scale = params_[drag_scale_] * mu_factor;
    const double eta_t = scale * c.eta_t, eta_p = scale * c.eta_p;
    const Vec3 v = ctx.nodeVelocity(n.node);
    const Mat3 A = eta_p * I + (eta_t - eta_p) * that * that.transpose();
    const Vec3 F =
        -n.voronoi_length * A * v;  // docs/model.md 2: F = -l [eta_p I + (eta_t - eta_p) t t^T] v
    force.segment<3>(3 * n.node) += F;
    if (!jacobian) continue;

    // Velocity part: dF/dx_j = -(l/dt) A.
    Mat3 d_self = -(n.voronoi_length / ctx.dt) * A;
    if (use_profile_ && mu_factor > 0.0) {  // dependence of the local viscosity on height
      const double dfactor = ctx.medium.profile.factorDerivative(height);
      d_self += (F / mu_factor) * (dfactor * ctx.medium.up).transpose();
    }
    // Geometric part (docs/model.md 2): dF/dthat, dthat/ds, ds/dx.
    const Mat3 dF_dthat =
        -n.voronoi_length * (eta_t - eta_p) * (that.dot(v) * I + that * v.transpose());
    const Mat3 dthat_ds = (I - that * that.transpose()) / s_norm;
    const Mat3 dF_ds = dF_dthat * dthat_ds;
    Mat3 ds_dprev = Mat3::Zero(), ds_dnext = Mat3::Zero();
    if (n.prev >= 0) ds_dprev = -(I - t_in * t_in.transpose()) / (len_in * edge_count);
    if (n.next >= 0) ds_dnext = (I - t_out * t_out.transpose()) / (len_out * edge_count);
    d_self += dF_ds * (-(ds_dprev + ds_dnext));
    jacobian->addBlock(3 * n.node, 3 * n.node, d_self);
    if (n.prev >= 0) jacobian->addBlock(3 * n.node, 3 * n.prev, dF_ds * ds_dprev);
    if (n.next >= 0) jacobian->addBlock(3 * n.node, 3 * n.next, dF_ds * ds_dnext);
  }
}

}  // namespace flagella
