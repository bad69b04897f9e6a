#include "flagella_sim/elastic/bend_twist_energy.h"

#include "flagella_sim/core/geometry.h"

namespace flagella {

namespace {

// Edge-space variables of one spring: [e(3), f(3), theta_E, theta_F].
using EdgeVector = Eigen::Matrix<double, 8, 1>;
using EdgeMatrix = Eigen::Matrix<double, 8, 8>;

// Chain rule from edge space to node space: e = x_c - x_p, f = x_q - x_c (docs/model.md 1.5).
SpringVector nodeGradient(const EdgeVector& g) {
  SpringVector out;
  out.segment<3>(0) = -g.segment<3>(0);
  out.segment<3>(3) = g.segment<3>(0) - g.segment<3>(3);
  out.segment<3>(6) = g.segment<3>(3);
  out(9) = g(6);
  out(10) = g(7);
  return out;
}

// docs/model.md 1.5: H_pp = g_ee, H_pc = -g_ee + g_ef, H_pq = -g_ef, H_cc = g_ee - g_ef - g_fe +
// g_ff, H_cq = g_ef - g_ff, H_qq = g_ff; theta columns map like the gradient.
void nodeHessian(const EdgeMatrix& h, SpringMatrix& out) {
  // Column by column (contiguous in both): column j of out is A^T (h A)(:, j), with A the map
  // from node space to edge space; the centre block keeps the sum's order ((ee - ef) - fe) + ff.
  auto column = [&out](int j, const Eigen::Matrix<double, 8, 1>& m) {
    double* o = out.data() + 11 * j;
    for (int k = 0; k < 3; ++k) {
      o[k] = -m(k);
      o[3 + k] = m(k) - m(3 + k);
      o[6 + k] = m(3 + k);
    }
    o[9] = m(6);
    o[10] = m(7);
  };
  for (int b = 0; b < 3; ++b) {
    column(b, -h.col(b));
    column(3 + b, h.col(b) - h.col(3 + b));
    for (int k = 0; k < 3; ++k)  // H_cc = ee - ef - fe + ff
      out(3 + k, 3 + b) = ((h(k, b) - h(k, 3 + b)) - h(3 + k, b)) + h(3 + k, 3 + b);
    column(6 + b, h.col(3 + b));
  }
  column(9, h.col(6));
  column(10, h.col(7));
}

Mat3 sym(const Vec3& a, const Vec3& b) { return a * b.transpose() + b * a.transpose(); }

// Quantities shared by the curvature derivatives of one spring (docs/model.md 1.5).
struct CurvatureFrame {
  double chi;         ///< 1 + t_e . t_f
  Vec3 tt, mt1, mt2;  ///< (t_e + t_f) / chi, (m1e + m1f) / chi, (m2e + m2f) / chi
  Vec3 tf_x_mt1, tf_x_mt2, te_x_mt1, te_x_mt2;
};

CurvatureFrame curvatureFrame(const SpringGeometry& g) {
  CurvatureFrame c;
  c.chi = 1.0 + g.te.dot(g.tf);
  const double inv_chi = 1.0 / c.chi;  // one division, then products (also below)
  c.tt = (g.te + g.tf) * inv_chi;
  c.mt1 = (g.m1e + g.m1f) * inv_chi;
  c.mt2 = (g.m2e + g.m2f) * inv_chi;
  c.tf_x_mt1 = g.tf.cross(c.mt1);
  c.tf_x_mt2 = g.tf.cross(c.mt2);
  c.te_x_mt1 = g.te.cross(c.mt1);
  c.te_x_mt2 = g.te.cross(c.mt2);
  return c;
}

struct CurvatureGradients {
  EdgeVector kappa1, kappa2, tau;
};

// docs/model.md 1.5: gradients of kappa1, kappa2 and tau in edge space.
CurvatureGradients curvatureGradients(const SpringGeometry& g, const CurvatureFrame& c) {
  CurvatureGradients d;
  const double inv_le = 1.0 / g.len_e, inv_lf = 1.0 / g.len_f;
  d.kappa1.segment<3>(0) = (-g.kappa1 * c.tt + c.tf_x_mt2) * inv_le;
  d.kappa1.segment<3>(3) = (-g.kappa1 * c.tt - c.te_x_mt2) * inv_lf;
  d.kappa1(6) = -0.5 * g.kb.dot(g.m1e);
  d.kappa1(7) = -0.5 * g.kb.dot(g.m1f);
  d.kappa2.segment<3>(0) = (-g.kappa2 * c.tt - c.tf_x_mt1) * inv_le;
  d.kappa2.segment<3>(3) = (-g.kappa2 * c.tt + c.te_x_mt1) * inv_lf;
  d.kappa2(6) = -0.5 * g.kb.dot(g.m2e);
  d.kappa2(7) = -0.5 * g.kb.dot(g.m2f);
  d.tau.segment<3>(0) = g.kb * (0.5 * inv_le);
  d.tau.segment<3>(3) = g.kb * (0.5 * inv_lf);
  d.tau(6) = -1.0;
  d.tau(7) = 1.0;
  return d;
}

// docs/model.md 1.5: w1 Hess(kappa1) + w2 Hess(kappa2) + wt Hess(tau) in edge space, summed block
// by block (the three Hessians are never formed on their own). With K = w1 kappa1 + w2 kappa2,
//   H_ee = [2K tt tt^T + sym(v_e, tt) - (K/chi) P_e + sym(kb, u_e)] / le^2,
//   H_ff = [2K tt tt^T + sym(v_f, tt) - (K/chi) P_f + sym(kb, u_f)] / lf^2,
//   H_ef = [-(K/chi)(I + t_e t_f^T) + 2K tt tt^T + v_e tt^T + tt v_f^T
//           + [w2 mt1 - w1 mt2 + (wt/chi) t_e]_x - (wt/2) kb tt^T] / (le lf),
// v_e = w2 (t_f x mt1) - w1 (t_f x mt2), v_f = w1 (t_e x mt2) - w2 (t_e x mt1),
// u_e = (w1 m2e - w2 m1e - wt (t_e + tt)) / 4, u_f = (w1 m2f - w2 m1f - wt (t_f + tt)) / 4;
// theta columns with n_k = w1 m1_k + w2 m2_k (k = E, F):
//   H_e,k = (kb.n_k tt / 2 - t_f x n_k / chi) / le,  H_f,k = (kb.n_k tt / 2 + t_e x n_k / chi) /
//   lf, H_EE = kb.(w2 m1e - w1 m2e) / 2, H_FF = kb.(w2 m1f - w1 m2f) / 2.
EdgeMatrix weightedCurvatureHessian(const SpringGeometry& g, const CurvatureFrame& c, double w1,
                                    double w2, double wt) {
  const double inv_le = 1.0 / g.len_e, inv_lf = 1.0 / g.len_f, inv_chi = 1.0 / c.chi;
  const double K = w1 * g.kappa1 + w2 * g.kappa2;
  const Mat3 I = Mat3::Identity();
  const Mat3 tt_tt = (2.0 * K) * (c.tt * c.tt.transpose());
  const Vec3 v_e = w2 * c.tf_x_mt1 - w1 * c.tf_x_mt2;
  const Vec3 v_f = w1 * c.te_x_mt2 - w2 * c.te_x_mt1;
  const Vec3 u_e = 0.25 * (w1 * g.m2e - w2 * g.m1e - wt * (g.te + c.tt));
  const Vec3 u_f = 0.25 * (w1 * g.m2f - w2 * g.m1f - wt * (g.tf + c.tt));
  const double k_chi = K * inv_chi;
  EdgeMatrix h;
  h.block<3, 3>(0, 0) =
      (tt_tt + sym(v_e, c.tt) - k_chi * (I - g.te * g.te.transpose()) + sym(g.kb, u_e)) *
      (inv_le * inv_le);
  h.block<3, 3>(3, 3) =
      (tt_tt + sym(v_f, c.tt) - k_chi * (I - g.tf * g.tf.transpose()) + sym(g.kb, u_f)) *
      (inv_lf * inv_lf);
  const Mat3 ef = (-k_chi * (I + g.te * g.tf.transpose()) + tt_tt + v_e * c.tt.transpose() +
                   c.tt * v_f.transpose() + skew(w2 * c.mt1 - w1 * c.mt2 + (wt * inv_chi) * g.te) -
                   (0.5 * wt) * g.kb * c.tt.transpose()) *
                  (inv_le * inv_lf);
  h.block<3, 3>(0, 3) = ef;
  h.block<3, 3>(3, 0) = ef.transpose();
  const Vec3 n[2] = {w1 * g.m1e + w2 * g.m2e, w1 * g.m1f + w2 * g.m2f};
  for (int k = 0; k < 2; ++k) {
    const double along = 0.5 * g.kb.dot(n[k]);
    const Vec3 col_e = (along * c.tt - g.tf.cross(n[k]) * inv_chi) * inv_le;
    const Vec3 col_f = (along * c.tt + g.te.cross(n[k]) * inv_chi) * inv_lf;
    h.block<3, 1>(0, 6 + k) = col_e;
    h.block<3, 1>(3, 6 + k) = col_f;
    h.block<1, 3>(6 + k, 0) = col_e.transpose();
    h.block<1, 3>(6 + k, 3) = col_f.transpose();
  }
  h(6, 6) = 0.5 * g.kb.dot(w2 * g.m1e - w1 * g.m2e);
  h(7, 7) = 0.5 * g.kb.dot(w2 * g.m1f - w1 * g.m2f);
  h(6, 7) = 0.0;
  h(7, 6) = 0.0;
  return h;
}

}  // namespace

SpringEnergyTerms bendTwistTerms(const SpringGeometry& g, const BendTwistSpring& s,
                                 bool with_hessian) {
  SpringEnergyTerms out;
  const double bend_k = s.EI / s.voronoi_length;
  const double twist_k = s.GJ / s.voronoi_length;
  const double dk1 = g.kappa1 - s.kappa_bar1;
  const double dk2 = g.kappa2 - s.kappa_bar2;
  const double dtau = g.tau - s.tau_bar;
  // docs/model.md 1.4: E_b = EI/(2 l_c) (dk1^2 + dk2^2), E_t = GJ/(2 l_c) dtau^2
  out.energy = 0.5 * bend_k * (dk1 * dk1 + dk2 * dk2) + 0.5 * twist_k * dtau * dtau;
  const CurvatureFrame frame = curvatureFrame(g);
  const CurvatureGradients d = curvatureGradients(g, frame);
  const EdgeVector grad_edge = bend_k * (dk1 * d.kappa1 + dk2 * d.kappa2) + twist_k * dtau * d.tau;
  out.gradient = nodeGradient(grad_edge);
  if (with_hessian) {
    // docs/model.md 1.5: Hess E_b = (EI/l_c)(g1 g1^T + g2 g2^T + dk1 H1 + dk2 H2), likewise E_t
    EdgeMatrix hess_edge =
        weightedCurvatureHessian(g, frame, bend_k * dk1, bend_k * dk2, twist_k * dtau);
    hess_edge.noalias() += bend_k * d.kappa1.lazyProduct(d.kappa1.transpose());
    hess_edge.noalias() += bend_k * d.kappa2.lazyProduct(d.kappa2.transpose());
    hess_edge.noalias() += twist_k * d.tau.lazyProduct(d.tau.transpose());
    nodeHessian(hess_edge, out.hessian);
  }
  return out;
}

SpringDofMap springDofMap(const RodNetwork& net, const BendTwistSpring& s) {
  SpringDofMap map;
  const int nodes[3] = {s.node_p, s.node_c, s.node_q};
  for (int n = 0; n < 3; ++n)
    for (int k = 0; k < 3; ++k) {
      map.index[3 * n + k] = 3 * nodes[n] + k;
      map.sign[3 * n + k] = 1.0;
    }
  map.index[9] = net.thetaIndex(s.edge_e);
  map.sign[9] = s.sign_e;
  map.index[10] = net.thetaIndex(s.edge_f);
  map.sign[10] = s.sign_f;
  return map;
}

BendTwistSpring drivenSpring(const RodNetwork& net, const NaturalTwistOverride& twist) {
  BendTwistSpring driven = net.bend_twist_springs.at(twist.spring);
  // docs/model.md 1.9: the shaft's frame turned back by the twist gained since t = 0
  driven.frame_turn = twist.tau_bar - driven.tau_bar;
  driven.tau_bar = twist.tau_bar;
  return driven;
}

double bendTwistEnergy(const RodNetwork& net, const VecX& q, const ReferenceFrames& frames,
                       const NaturalTwistOverride& twist) {
  double energy = 0.0;
  BendTwistSpring driven;
  if (twist.spring >= 0) driven = drivenSpring(net, twist);
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    const BendTwistSpring& s =
        static_cast<int>(i) == twist.spring ? driven : net.bend_twist_springs[i];
    energy +=
        bendTwistTerms(springGeometry(net, s, q, frames, static_cast<int>(i)), s, false).energy;
  }
  return energy;
}

void addBendTwistGradientHessian(const RodNetwork& net, const VecX& q,
                                 const ReferenceFrames& frames, VecX& gradient,
                                 SparseAssembler* hessian, const NaturalTwistOverride& twist) {
  BendTwistSpring driven;
  if (twist.spring >= 0) driven = drivenSpring(net, twist);
  thread_local MaterialFrames material;  // storage reused across calls
  materialFrames(net, q, frames, material);
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    const BendTwistSpring& s =
        static_cast<int>(i) == twist.spring ? driven : net.bend_twist_springs[i];
    SpringEnergyTerms terms = bendTwistTerms(
        springGeometry(net, s, q, frames, material, static_cast<int>(i)), s, hessian);
    const SpringDofMap map = springDofMap(net, s);
    // docs/model.md 1.6: dE/dtheta^g = s_g dE/dtheta_loc; mixed entries carry both signs (only
    // the two twist DOFs have a sign)
    for (int a = 9; a < 11; ++a) {
      if (map.sign[a] > 0.0) continue;  // +1: nothing to flip
      terms.gradient(a) = -terms.gradient(a);
      if (!hessian) continue;
      terms.hessian.row(a) *= -1.0;
      terms.hessian.col(a) *= -1.0;
    }
    for (int a = 0; a < 11; ++a) gradient(map.index[a]) += terms.gradient(a);
    if (!hessian) continue;
    hessian->addDense<11>(map.index, terms.hessian);
  }
}

}  // namespace flagella
