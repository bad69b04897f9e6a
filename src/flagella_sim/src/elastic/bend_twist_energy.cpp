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
SpringMatrix nodeHessian(const EdgeMatrix& h) {
  SpringMatrix out;
  const Mat3 ee = h.block<3, 3>(0, 0), ef = h.block<3, 3>(0, 3), fe = h.block<3, 3>(3, 0),
             ff = h.block<3, 3>(3, 3);
  out.block<3, 3>(0, 0) = ee;
  out.block<3, 3>(0, 3) = ef - ee;
  out.block<3, 3>(0, 6) = -ef;
  out.block<3, 3>(3, 0) = fe - ee;
  out.block<3, 3>(3, 3) = ee - ef - fe + ff;
  out.block<3, 3>(3, 6) = ef - ff;
  out.block<3, 3>(6, 0) = -fe;
  out.block<3, 3>(6, 3) = fe - ff;
  out.block<3, 3>(6, 6) = ff;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Matrix<double, 3, 1> e_th = h.block<3, 1>(0, 6 + k),
                                      f_th = h.block<3, 1>(3, 6 + k);
    const Eigen::Matrix<double, 9, 1> col =
        (Eigen::Matrix<double, 9, 1>() << -e_th, e_th - f_th, f_th).finished();
    out.block<9, 1>(0, 9 + k) = col;
    out.block<1, 9>(9 + k, 0) = col.transpose();
    out(9 + k, 9) = h(6 + k, 6);
    out(9 + k, 10) = h(6 + k, 7);
  }
  return out;
}

Mat3 sym(const Vec3& a, const Vec3& b) { return a * b.transpose() + b * a.transpose(); }

struct CurvatureDerivatives {
  EdgeVector grad1, grad2, grad_tau;
  EdgeMatrix hess1, hess2, hess_tau;
};

// docs/model.md 1.5: gradients and Hessians of kappa1, kappa2 and tau in edge space.
CurvatureDerivatives curvatureDerivatives(const SpringGeometry& g, bool with_hessian) {
  CurvatureDerivatives d;
  const double chi = 1.0 + g.te.dot(g.tf);
  const Vec3 tt = (g.te + g.tf) / chi;
  const Vec3 mt1 = (g.m1e + g.m1f) / chi;
  const Vec3 mt2 = (g.m2e + g.m2f) / chi;
  const double le = g.len_e, lf = g.len_f;
  const double k1 = g.kappa1, k2 = g.kappa2;
  const Vec3 tf_x_mt1 = g.tf.cross(mt1), tf_x_mt2 = g.tf.cross(mt2);
  const Vec3 te_x_mt1 = g.te.cross(mt1), te_x_mt2 = g.te.cross(mt2);

  d.grad1.segment<3>(0) = (-k1 * tt + tf_x_mt2) / le;
  d.grad1.segment<3>(3) = (-k1 * tt - te_x_mt2) / lf;
  d.grad1(6) = -0.5 * g.kb.dot(g.m1e);
  d.grad1(7) = -0.5 * g.kb.dot(g.m1f);
  d.grad2.segment<3>(0) = (-k2 * tt - tf_x_mt1) / le;
  d.grad2.segment<3>(3) = (-k2 * tt + te_x_mt1) / lf;
  d.grad2(6) = -0.5 * g.kb.dot(g.m2e);
  d.grad2(7) = -0.5 * g.kb.dot(g.m2f);
  d.grad_tau.segment<3>(0) = g.kb / (2.0 * le);
  d.grad_tau.segment<3>(3) = g.kb / (2.0 * lf);
  d.grad_tau(6) = -1.0;
  d.grad_tau(7) = 1.0;
  if (!with_hessian) return d;

  const Mat3 I = Mat3::Identity();
  const Mat3 tt_tt = tt * tt.transpose();
  const Mat3 pe = I - g.te * g.te.transpose();
  const Mat3 pf = I - g.tf * g.tf.transpose();
  const Mat3 cross_ef = I + g.te * g.tf.transpose();

  d.hess1.setZero();
  d.hess1.block<3, 3>(0, 0) =
      (2.0 * k1 * tt_tt - tf_x_mt2 * tt.transpose() - tt * tf_x_mt2.transpose()) / (le * le) -
      k1 / (chi * le * le) * pe + sym(g.kb, g.m2e) / (4.0 * le * le);
  d.hess1.block<3, 3>(3, 3) =
      (2.0 * k1 * tt_tt + te_x_mt2 * tt.transpose() + tt * te_x_mt2.transpose()) / (lf * lf) -
      k1 / (chi * lf * lf) * pf + sym(g.kb, g.m2f) / (4.0 * lf * lf);
  const Mat3 h1_ef =
      -k1 / (chi * le * lf) * cross_ef +
      (2.0 * k1 * tt_tt - tf_x_mt2 * tt.transpose() + tt * te_x_mt2.transpose() - skew(mt2)) /
          (le * lf);
  d.hess1.block<3, 3>(0, 3) = h1_ef;
  d.hess1.block<3, 3>(3, 0) = h1_ef.transpose();
  d.hess1(6, 6) = -0.5 * g.kb.dot(g.m2e);
  d.hess1(7, 7) = -0.5 * g.kb.dot(g.m2f);

  d.hess2.setZero();
  d.hess2.block<3, 3>(0, 0) =
      (2.0 * k2 * tt_tt + tf_x_mt1 * tt.transpose() + tt * tf_x_mt1.transpose()) / (le * le) -
      k2 / (chi * le * le) * pe - sym(g.kb, g.m1e) / (4.0 * le * le);
  d.hess2.block<3, 3>(3, 3) =
      (2.0 * k2 * tt_tt - te_x_mt1 * tt.transpose() - tt * te_x_mt1.transpose()) / (lf * lf) -
      k2 / (chi * lf * lf) * pf - sym(g.kb, g.m1f) / (4.0 * lf * lf);
  const Mat3 h2_ef =
      -k2 / (chi * le * lf) * cross_ef +
      (2.0 * k2 * tt_tt + tf_x_mt1 * tt.transpose() - tt * te_x_mt1.transpose() + skew(mt1)) /
          (le * lf);
  d.hess2.block<3, 3>(0, 3) = h2_ef;
  d.hess2.block<3, 3>(3, 0) = h2_ef.transpose();
  d.hess2(6, 6) = 0.5 * g.kb.dot(g.m1e);
  d.hess2(7, 7) = 0.5 * g.kb.dot(g.m1f);

  // Position-theta cross blocks (docs/model.md 1.5), for theta_E (column 6) and theta_F (column 7).
  const Vec3* m1[2] = {&g.m1e, &g.m1f};
  const Vec3* m2[2] = {&g.m2e, &g.m2f};
  for (int k = 0; k < 2; ++k) {
    const int col = 6 + k;
    const Vec3 k1_e = (0.5 * g.kb.dot(*m1[k]) * tt - g.tf.cross(*m1[k]) / chi) / le;
    const Vec3 k1_f = (0.5 * g.kb.dot(*m1[k]) * tt + g.te.cross(*m1[k]) / chi) / lf;
    const Vec3 k2_e = (0.5 * g.kb.dot(*m2[k]) * tt - g.tf.cross(*m2[k]) / chi) / le;
    const Vec3 k2_f = (0.5 * g.kb.dot(*m2[k]) * tt + g.te.cross(*m2[k]) / chi) / lf;
    d.hess1.block<3, 1>(0, col) = k1_e;
    d.hess1.block<3, 1>(3, col) = k1_f;
    d.hess1.block<1, 3>(col, 0) = k1_e.transpose();
    d.hess1.block<1, 3>(col, 3) = k1_f.transpose();
    d.hess2.block<3, 1>(0, col) = k2_e;
    d.hess2.block<3, 1>(3, col) = k2_f;
    d.hess2.block<1, 3>(col, 0) = k2_e.transpose();
    d.hess2.block<1, 3>(col, 3) = k2_f.transpose();
  }

  d.hess_tau.setZero();
  d.hess_tau.block<3, 3>(0, 0) = -sym(g.kb, g.te + tt) / (4.0 * le * le);
  d.hess_tau.block<3, 3>(3, 3) = -sym(g.kb, g.tf + tt) / (4.0 * lf * lf);
  const Mat3 ht_ef = ((2.0 / chi) * skew(g.te) - g.kb * tt.transpose()) / (2.0 * le * lf);
  d.hess_tau.block<3, 3>(0, 3) = ht_ef;
  d.hess_tau.block<3, 3>(3, 0) = ht_ef.transpose();
  return d;
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
  const CurvatureDerivatives d = curvatureDerivatives(g, with_hessian);
  const EdgeVector grad_edge =
      bend_k * (dk1 * d.grad1 + dk2 * d.grad2) + twist_k * dtau * d.grad_tau;
  out.gradient = nodeGradient(grad_edge);
  if (with_hessian) {
    // docs/model.md 1.5: Hess E_b = (EI/l_c)(g1 g1^T + g2 g2^T + dk1 H1 + dk2 H2), likewise E_t
    EdgeMatrix hess_edge = bend_k * (dk1 * d.hess1 + dk2 * d.hess2) + twist_k * dtau * d.hess_tau;
    hess_edge.noalias() += bend_k * d.grad1.lazyProduct(d.grad1.transpose());
    hess_edge.noalias() += bend_k * d.grad2.lazyProduct(d.grad2.transpose());
    hess_edge.noalias() += twist_k * d.grad_tau.lazyProduct(d.grad_tau.transpose());
    out.hessian = nodeHessian(hess_edge);
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

double bendTwistEnergy(const RodNetwork& net, const VecX& q, const ReferenceFrames& frames) {
  double energy = 0.0;
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    const BendTwistSpring& s = net.bend_twist_springs[i];
    energy +=
        bendTwistTerms(springGeometry(net, s, q, frames, static_cast<int>(i)), s, false).energy;
  }
  return energy;
}

void addBendTwistGradientHessian(const RodNetwork& net, const VecX& q,
                                 const ReferenceFrames& frames, VecX& gradient,
                                 SparseAssembler* hessian, const NaturalTwistOverride& twist) {
  BendTwistSpring driven;
  if (twist.spring >= 0) {
    driven = net.bend_twist_springs.at(twist.spring);
    driven.tau_bar = twist.tau_bar;
  }
  for (size_t i = 0; i < net.bend_twist_springs.size(); ++i) {
    const BendTwistSpring& s =
        static_cast<int>(i) == twist.spring ? driven : net.bend_twist_springs[i];
    const SpringEnergyTerms terms =
        bendTwistTerms(springGeometry(net, s, q, frames, static_cast<int>(i)), s, hessian);
    const SpringDofMap map = springDofMap(net, s);
    // docs/model.md 1.6: dE/dtheta^g = s_g dE/dtheta_loc; mixed entries carry both signs
    for (int a = 0; a < 11; ++a) gradient(map.index[a]) += map.sign[a] * terms.gradient(a);
    if (!hessian) continue;
    hessian->addDense<11>(map.index, map.sign, terms.hessian);
  }
}

}  // namespace flagella
