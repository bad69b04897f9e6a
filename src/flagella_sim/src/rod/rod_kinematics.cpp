#include "flagella_sim/rod/rod_kinematics.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

#include "flagella_sim/core/geometry.h"

namespace flagella {

namespace {

constexpr double kTwoPi = 6.283185307179586;

Vec3 edgeVector(const RodNetwork& net, const VecX& q, int edge) {
  const EdgeDef& e = net.edges[edge];
  return nodePosition(q, e.end_node) - nodePosition(q, e.start_node);
}

// Unit tangents and lengths of every edge (stored orientation).
void unitTangents(const RodNetwork& net, const VecX& q, ReferenceFrames& fr) {
  fr.tangent.resize(net.numEdges());
  fr.edge_length.resize(net.numEdges());
  for (int j = 0; j < net.numEdges(); ++j) {
    const Vec3 e = edgeVector(net, q, j);
    fr.edge_length[j] = e.norm();
    fr.tangent[j] = e * (1.0 / fr.edge_length[j]);
  }
}

// Material directors of one edge (stored orientation, docs/model.md 1.2):
// m1 = cos(theta) d1 + sin(theta) d2, m2 = -sin(theta) d1 + cos(theta) d2.
struct EdgeDirectors {
  Vec3 m1, m2;
};
EdgeDirectors edgeDirectors(const RodNetwork& net, const VecX& q, const ReferenceFrames& fr,
                            int edge) {
  const double th = q(net.thetaIndex(edge));
  const double c = std::cos(th), s = std::sin(th);
  return {c * fr.d1[edge] + s * fr.d2[edge], -s * fr.d1[edge] + c * fr.d2[edge]};
}

// Reference twist of spring s measured directly (no history): signed angle from the
// parallel-transported local d1 of E to the local d1 of F, about t_f (docs/model.md 1.3).
double directReferenceTwist(const BendTwistSpring& s, const ReferenceFrames& fr) {
  const Vec3 te = s.sign_e * fr.tangent[s.edge_e];
  const Vec3 tf = s.sign_f * fr.tangent[s.edge_f];
  const Vec3 d1e = s.sign_e * fr.d1[s.edge_e];
  const Vec3 d1f = s.sign_f * fr.d1[s.edge_f];
  return angleAbout(parallelTransport(d1e, te, tf), d1f, tf);
}

}  // namespace

ReferenceFrames initialFrames(const RodNetwork& net, const VecX& q, int root_edge) {
  const int ne = net.numEdges();
  ReferenceFrames fr;
  unitTangents(net, q, fr);
  fr.d1.assign(ne, Vec3::Zero());
  fr.d2.assign(ne, Vec3::Zero());

  // Edges incident to each node, for the breadth-first walk over the tree.
  std::vector<std::vector<int>> incident(net.numNodes());
  for (int j = 0; j < ne; ++j) {
    incident[net.edges[j].start_node].push_back(j);
    incident[net.edges[j].end_node].push_back(j);
  }
  std::vector<bool> done(ne, false);
  std::queue<int> queue;
  fr.d1[root_edge] = anyPerpendicular(fr.tangent[root_edge]);
  done[root_edge] = true;
  queue.push(root_edge);
  while (!queue.empty()) {
    const int h = queue.front();
    queue.pop();
    for (int node : {net.edges[h].start_node, net.edges[h].end_node}) {
      for (int g : incident[node]) {
        if (done[g]) continue;
        // Orient h into the shared node and g out of it, transport there (docs/model.md 1.6, 1.7).
        const double sh = net.edges[h].end_node == node ? 1.0 : -1.0;
        const double sg = net.edges[g].start_node == node ? 1.0 : -1.0;
        const Vec3 d1g_local =
            parallelTransport(sh * fr.d1[h], sh * fr.tangent[h], sg * fr.tangent[g]);
        const Vec3 tg = fr.tangent[g];
        fr.d1[g] = (sg * d1g_local - (sg * d1g_local).dot(tg) * tg).normalized();
        done[g] = true;
        queue.push(g);
      }
    }
  }
  for (int j = 0; j < ne; ++j) {
    if (!done[j])
      throw std::invalid_argument("rod network is not connected: edge " + std::to_string(j) +
                                  " unreachable");
    fr.d2[j] = fr.tangent[j].cross(fr.d1[j]);
  }
  fr.reference_twist.resize(net.bend_twist_springs.size());
  for (size_t s = 0; s < net.bend_twist_springs.size(); ++s)
    fr.reference_twist[s] = directReferenceTwist(net.bend_twist_springs[s], fr);
  return fr;
}

ReferenceFrames transportFrames(const RodNetwork& net, const VecX& q,
                                const ReferenceFrames& previous) {
  ReferenceFrames fr;
  transportFrames(net, q, previous, fr);
  return fr;
}

void transportFrames(const RodNetwork& net, const VecX& q, const ReferenceFrames& previous,
                     ReferenceFrames& fr) {
  const int ne = net.numEdges();
  unitTangents(net, q, fr);
  fr.d1.resize(ne);
  fr.d2.resize(ne);
  for (int j = 0; j < ne; ++j) {
    // docs/model.md 1.7: d1(iterate) = P_{t(t_k) -> t(iterate)} d1(t_k), d2 = t x d1
    const Vec3 d1 = parallelTransport(previous.d1[j], previous.tangent[j], fr.tangent[j]);
    fr.d1[j] = unitVector(d1 - d1.dot(fr.tangent[j]) * fr.tangent[j]);
    fr.d2[j] = fr.tangent[j].cross(fr.d1[j]);
  }
  fr.reference_twist.resize(net.bend_twist_springs.size());
  for (size_t s = 0; s < net.bend_twist_springs.size(); ++s) {
    const BendTwistSpring& sp = net.bend_twist_springs[s];
    const Vec3 te = sp.sign_e * fr.tangent[sp.edge_e];
    const Vec3 tf = sp.sign_f * fr.tangent[sp.edge_f];
    const Vec3 d1e = sp.sign_e * fr.d1[sp.edge_e];
    const Vec3 d1f = sp.sign_f * fr.d1[sp.edge_f];
    // docs/model.md 1.3: m_ref = old + (the signed angle from P(d1_E) rotated by old about t_f to
    // d1_F), i.e. old + the angle from P(d1_E) to d1_F minus old, wrapped to (-pi, pi]
    const double old_twist = previous.reference_twist[s];
    const double change = angleAbout(parallelTransport(d1e, te, tf), d1f, tf) - old_twist;
    // (std::round is a library call: skipped in the usual case, |change| < pi, where it is 0)
    const double wrapped =
        std::abs(change) < 0.5 * kTwoPi ? change : change - kTwoPi * std::round(change / kTwoPi);
    fr.reference_twist[s] = old_twist + wrapped;
  }
}

void materialFrames(const RodNetwork& net, const VecX& q, const ReferenceFrames& fr,
                    MaterialFrames& out) {
  const int ne = net.numEdges();
  out.m1.resize(ne);
  out.m2.resize(ne);
  for (int j = 0; j < ne; ++j) {
    const EdgeDirectors m = edgeDirectors(net, q, fr, j);
    out.m1[j] = m.m1;
    out.m2[j] = m.m2;
  }
}

namespace {

// The spring's geometry once its local material directors are known.
SpringGeometry springGeometryWith(const RodNetwork& net, const BendTwistSpring& sp, const VecX& q,
                                  const ReferenceFrames& fr, int spring_index, const Vec3& m1e,
                                  const Vec3& m2e, const Vec3& m1f, const Vec3& m2f) {
  // The edges' tangents and lengths at q come with the frames (transported to q): the local
  // tangent is the stored one times the orientation sign (docs/model.md 1.6).
  SpringGeometry g;
  g.len_e = fr.edge_length[sp.edge_e];
  g.len_f = fr.edge_length[sp.edge_f];
  g.te = sp.sign_e * fr.tangent[sp.edge_e];
  g.tf = sp.sign_f * fr.tangent[sp.edge_f];
  g.m1e = m1e;
  g.m2e = m2e;
  if (sp.frame_turn == 0.0) {
    g.m1f = m1f;
    g.m2f = m2f;
  } else {  // docs/model.md 1.9: F's directors at theta_F - frame_turn
    const double c = std::cos(sp.frame_turn), s = std::sin(sp.frame_turn);
    g.m1f = c * m1f - s * m2f;
    g.m2f = s * m1f + c * m2f;
  }
  // docs/model.md 1.3: kb = 2 (t_e x t_f) / (1 + t_e.t_f), kappa1 = 1/2 (m2e+m2f).kb, kappa2 = -1/2
  // (m1e+m1f).kb
  g.kb = g.te.cross(g.tf) * (2.0 / (1.0 + g.te.dot(g.tf)));
  g.kappa1 = 0.5 * (g.m2e + g.m2f).dot(g.kb);
  g.kappa2 = -0.5 * (g.m1e + g.m1f).dot(g.kb);
  const double theta_e = sp.sign_e * q(net.thetaIndex(sp.edge_e));
  const double theta_f = sp.sign_f * q(net.thetaIndex(sp.edge_f));
  g.tau = theta_f - theta_e + fr.reference_twist[spring_index];  // docs/model.md 1.3 [CORR-9]
  return g;
}

}  // namespace

SpringGeometry springGeometry(const RodNetwork& net, const BendTwistSpring& sp, const VecX& q,
                              const ReferenceFrames& fr, int spring_index) {
  // Local material frames (docs/model.md 1.6): m1_loc = s m1, m2_loc = m2, theta_loc = s theta.
  const EdgeDirectors e = edgeDirectors(net, q, fr, sp.edge_e);
  const EdgeDirectors f = edgeDirectors(net, q, fr, sp.edge_f);
  return springGeometryWith(net, sp, q, fr, spring_index, sp.sign_e * e.m1, e.m2, sp.sign_f * f.m1,
                            f.m2);
}

SpringGeometry springGeometry(const RodNetwork& net, const BendTwistSpring& sp, const VecX& q,
                              const ReferenceFrames& fr, const MaterialFrames& material,
                              int spring_index) {
  // docs/model.md 1.6: the local m1 is s m1 of the edge, the local m2 its m2 (cos even, sin odd).
  return springGeometryWith(net, sp, q, fr, spring_index, sp.sign_e * material.m1[sp.edge_e],
                            material.m2[sp.edge_e], sp.sign_f * material.m1[sp.edge_f],
                            material.m2[sp.edge_f]);
}

Vec3 materialDirector1(const ReferenceFrames& fr, const VecX& q, const RodNetwork& net, int edge) {
  return edgeDirectors(net, q, fr, edge).m1;
}

FoldedJoint mostFoldedJoint(const RodNetwork& net, const ReferenceFrames& frames) {
  FoldedJoint most;
  double lowest = 2.0;  // cosine of the turning angle t_e . t_f (docs/model.md 1.3)
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    const BendTwistSpring& b = net.bend_twist_springs[i];
    const double c = (b.sign_e * frames.tangent[b.edge_e]).dot(b.sign_f * frames.tangent[b.edge_f]);
    if (c < lowest) lowest = c, most.spring = static_cast<int>(i);
  }
  if (most.spring >= 0) most.angle = std::acos(std::clamp(lowest, -1.0, 1.0));
  return most;
}

}  // namespace flagella
