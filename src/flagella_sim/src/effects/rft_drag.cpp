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
      TailNode n;
      n.node = tail[i];
      n.voronoi_length = 0.5 * (before + after);
      n.tail_length = length;
      n.tail_radius = radius;
      if (i > 0) {
        n.prev = tail[i - 1];
        n.edge_in = edges[i - 1];
        n.sign_in = net.edges[n.edge_in].end_node == n.node ? 1.0 : -1.0;
      }
      if (i + 1 < tail.size()) {
        n.next = tail[i + 1];
        n.edge_out = edges[i];
        n.sign_out = net.edges[n.edge_out].start_node == n.node ? 1.0 : -1.0;
      }
      nodes_.push_back(n);
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

namespace {

// A tail node's tangent s and its adjacent edges' oriented unit tangents and inverse lengths.
struct NodeTangent {
  Vec3 s = Vec3::Zero();
  Vec3 t_in = Vec3::Zero(), t_out = Vec3::Zero();
  double inv_len_in = 0.0, inv_len_out = 0.0;
  int edge_count = 0;
};

// The node's unnormalised tangent s, mean of its adjacent edges' oriented tangents [CORR-4].
NodeTangent nodeTangent(const ReferenceFrames& fr, bool has_in, int edge_in, double sign_in,
                        bool has_out, int edge_out, double sign_out) {
  NodeTangent g;
  if (has_in) {
    g.t_in = sign_in * fr.tangent[edge_in];
    g.inv_len_in = 1.0 / fr.edge_length[edge_in];
    g.s += g.t_in;
    ++g.edge_count;
  }
  if (has_out) {
    g.t_out = sign_out * fr.tangent[edge_out];
    g.inv_len_out = 1.0 / fr.edge_length[edge_out];
    g.s += g.t_out;
    ++g.edge_count;
  }
  g.s *= 1.0 / g.edge_count;
  return g;
}

// Velocity part of the node's own block, -(l/dt) [eta_p I + (eta_t - eta_p) t t^T].
Mat3 velocityBlock(double l, double dt, double eta_t, double eta_p, const Vec3& that) {
  // (The 3x3 blocks are written coefficient by coefficient: the same arithmetic as the matrix
  // expressions, without their mixed scalar/packed temporaries.)
  const double along = -(l / dt) * (eta_t - eta_p);
  const double across = (l / dt) * eta_p;
  Mat3 d_self;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) d_self(r, c) = (along * that(r)) * that(c);
  for (int k = 0; k < 3; ++k) d_self(k, k) -= across;
  return d_self;
}

// dF/ds = ds_scale ((t.v)(I - t t^T) + t w^T) with w = v - (t.v) t (docs/model.md 2).
Mat3 forceTangentDerivative(const Vec3& that, const Vec3& v, double tv, double ds_scale) {
  const Vec3 w = v - tv * that;
  Mat3 dF_ds;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) dF_ds(r, c) = that(r) * (w(c) - tv * that(c));
  for (int k = 0; k < 3; ++k) dF_ds(k, k) += tv;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) dF_ds(r, c) *= ds_scale;
  return dF_ds;
}

// factor dF/ds (I - t_e t_e^T), without forming the projector, into `out`; d_self -= out.
void projectedBlock(const Mat3& dF_ds, const Vec3& t_e, double factor, Mat3& out, Mat3& d_self) {
  double u[3];
  for (int r = 0; r < 3; ++r)
    u[r] = (dF_ds(r, 0) * t_e(0) + dF_ds(r, 1) * t_e(1)) + dF_ds(r, 2) * t_e(2);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      out(r, c) = (dF_ds(r, c) - u[r] * t_e(c)) * factor;
      d_self(r, c) -= out(r, c);
    }
}

}  // namespace

void RftDrag::addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const {
  // Edge tangents and lengths at ctx.q come with the frames (transported to q).
  const ReferenceFrames& fr = ctx.frames;
  for (const TailNode& n : nodes_) {
    const Vec3 x = nodePosition(ctx.q, n.node);
    // docs/model.md 2: node tangent s = (t^{j-1} + t^j)/2 normalised; single edge at the ends
    // [CORR-4]
    const NodeTangent g =
        nodeTangent(fr, n.prev >= 0, n.edge_in, n.sign_in, n.next >= 0, n.edge_out, n.sign_out);
    const double inv_s_norm = 1.0 / g.s.norm();
    const Vec3 that = g.s * inv_s_norm;
    const RftCoefficients c = coefficients(n, ctx.viscosity);
    const double height = x.dot(ctx.medium.up);
    const double mu_factor = use_profile_ ? ctx.medium.profile.factor(height) : 1.0;
    const double scale = params_[drag_scale_] * mu_factor;
    const double eta_t = scale * c.eta_t, eta_p = scale * c.eta_p;
    const double l = n.voronoi_length;
    const Vec3 v = ctx.nodeVelocity(n.node);
    const double tv = that.dot(v);
    // docs/model.md 2: F = -l [eta_p I + (eta_t - eta_p) t t^T] v
    const Vec3 F = -l * (eta_p * v + ((eta_t - eta_p) * tv) * that);
    force.segment<3>(3 * n.node) += F;
    if (!jacobian) continue;

    // Velocity part: dF/dx_j = -(l/dt) [eta_p I + (eta_t - eta_p) t t^T].
    Mat3 d_self = velocityBlock(l, ctx.dt, eta_t, eta_p, that);
    if (use_profile_ && mu_factor > 0.0) {  // dependence of the local viscosity on height
      const double dfactor = ctx.medium.profile.factorDerivative(height);
      d_self += (F / mu_factor) * (dfactor * ctx.medium.up).transpose();
    }
    // Geometric part (docs/model.md 2): dF/dthat = -l (eta_t - eta_p) ((t.v) I + t v^T) times
    // dthat/ds = (I - t t^T)/|s|, i.e. dF/ds = -(l (eta_t - eta_p)/|s|) ((t.v)(I - t t^T) + t w^T)
    // with w = v - (t.v) t; ds/dx of a neighbour is -+(I - t_e t_e^T)/(|e| edges).
    const Mat3 dF_ds = forceTangentDerivative(that, v, tv, -l * (eta_t - eta_p) * inv_s_norm);
    if (n.prev >= 0) {
      Mat3 d_prev;
      projectedBlock(dF_ds, g.t_in, -g.inv_len_in / g.edge_count, d_prev, d_self);
      jacobian->addBlock(3 * n.node, 3 * n.prev, d_prev);
    }
    Mat3 d_next;
    if (n.next >= 0) projectedBlock(dF_ds, g.t_out, g.inv_len_out / g.edge_count, d_next, d_self);
    jacobian->addBlock(3 * n.node, 3 * n.node, d_self);
    if (n.next >= 0) jacobian->addBlock(3 * n.node, 3 * n.next, d_next);
  }
}

}  // namespace flagella
