// The RSS effect in the implicit step (docs/model.md 4.4): its dense Jacobian block against finite
// differences of its force, option A against option B, and a sedimenting rod whose steady
// hydrodynamic force balances the applied load (force balance at zero Reynolds number).
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "flagella_sim/effects/constant_load.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/effects/rss_hydrodynamics.h"
#include "flagella_sim/hydro/rss_solver.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "support/temp_dir.h"
#include "support/test_robots.h"

namespace flagella {
namespace {

class CapturingSink : public DenseJacobianSink {
 public:
  explicit CapturingSink(int n) : J(MatX::Zero(n, n)) {}
  void addDense(const std::vector<int>& dofs, const MatX& block, double scale) override {
    for (size_t c = 0; c < dofs.size(); ++c)
      for (size_t r = 0; r < dofs.size(); ++r) J(dofs[r], dofs[c]) += scale * block(r, c);
  }
  MatX J;
};

struct Fixture {
  RodNetwork net;
  Medium medium;
  RodState start;
  VecX q;
  double dt = 0.01;
};

// A three-tail robot bent and moving at random: three chains share one RSS system.
Fixture makeFixture(unsigned seed) {
  Fixture f{testing::makeThreeTailRobot(6), Medium(), {}, {}, 0.01};
  f.medium.parameters().set("viscosity", 1.3);
  std::mt19937 rng(seed);
  f.start.q = testing::perturbed(f.net, f.net.restDofs(), 2e-3, 0.5, rng);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  f.start.qdot = VecX::NullaryExpr(f.net.ndof(), [&] { return u(rng); });
  f.start.frames = initialFrames(f.net, f.start.q);
  f.q = testing::perturbed(f.net, f.start.q, 1e-3, 0.3, rng);
  return f;
}

VecX forceAt(const RssHydrodynamics& e, const Fixture& f, const VecX& q) {
  const ReferenceFrames fr = transportFrames(f.net, q, f.start.frames);
  VecX F = VecX::Zero(f.net.ndof());
  e.addForce({f.net, q, fr, f.start.q, f.start.qdot, f.dt, f.dt, f.medium, f.medium.viscosity()}, F,
             nullptr);
  return F;
}

/// An RSS effect with a fixed eps [m].
std::unique_ptr<RssHydrodynamics> rssWithEps(double eps, bool implicit) {
  auto e = std::make_unique<RssHydrodynamics>(1e-3, implicit);
  e->parameters().set("eps", eps);
  return e;
}

void beginStep(RssHydrodynamics& e, const Fixture& f) {
  e.attach(f.net);
  e.beginStep({f.net, f.start, f.dt, f.medium, f.medium.viscosity()});
}

TEST(RssEffect, DenseJacobianMatchesFiniteDifferences) {
  const Fixture f = makeFixture(7);
  const auto rss = rssWithEps(2e-3, true);
  RssHydrodynamics& e = *rss;
  beginStep(e, f);
  EXPECT_EQ(e.nodes().size(), 3u * 7u);  // every tail chain, root (disc rim) included
  ASSERT_TRUE(e.hasDenseJacobian());
  CapturingSink sink(f.net.ndof());
  const ReferenceFrames fr = transportFrames(f.net, f.q, f.start.frames);
  e.addDenseJacobian({f.net, f.q, fr, f.start.q, f.start.qdot, f.dt, f.dt, f.medium, 1.3}, sink);
  const double h = 1e-7;
  MatX J_fd(f.net.ndof(), f.net.ndof());
  for (int i = 0; i < f.net.ndof(); ++i) {
    VecX qp = f.q, qm = f.q;
    qp(i) += h;
    qm(i) -= h;
    J_fd.col(i) = (forceAt(e, f, qp) - forceAt(e, f, qm)) / (2 * h);
  }
  const double scale = J_fd.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT((sink.J - J_fd).cwiseAbs().maxCoeff(), 1e-6 * scale);
}

TEST(RssEffect, ExplicitOptionIsImplicitForceAtStartVelocities) {
  const Fixture f = makeFixture(8);
  const auto rss_b = rssWithEps(2e-3, true), rss_a = rssWithEps(2e-3, false);
  RssHydrodynamics &implicit = *rss_b, &explicit_a = *rss_a;
  beginStep(implicit, f);
  beginStep(explicit_a, f);
  EXPECT_FALSE(explicit_a.hasDenseJacobian());
  // Option B at x = x_k + dt xdot_k has the implicit velocity xdot_k: the force of option A.
  const VecX b = forceAt(implicit, f, f.start.q + f.dt * f.start.qdot);
  const VecX a = forceAt(explicit_a, f, f.q);
  ASSERT_GT(a.norm(), 0.0);
  EXPECT_LT((a - b).norm(), 1e-10 * a.norm());
  EXPECT_EQ(forceAt(explicit_a, f, f.start.q), a);  // held fixed over the step
  // Only tail node positions feel it.
  for (int node : implicit.nodes()) EXPECT_GE(node, 3);
  for (int i = 0; i < 3 * 3; ++i) EXPECT_EQ(a(i), 0.0);
}

// Keeps the matrix and row weights of the effect's inverse block (its Ablk and 8 pi mu l_p).
class InverseBlockSink : public DenseJacobianSink {
 public:
  void addDense(const std::vector<int>&, const MatX&, double) override {}
  void addScaledInverse(const std::vector<int>& dofs, const FactoredMatrix& a, const VecX&,
                        double) override {
    block_dofs = dofs;
    matrix = &a;
  }
  std::vector<int> block_dofs;
  const FactoredMatrix* matrix = nullptr;
};

TEST(RssEffect, FollowedIteratesHaveTheForceOfASolveWithoutOne) {
  // docs/model.md 4.4: after q -= C z (C maps by Ablk / alpha), the effect takes the force from
  // the followed preimage g -= z / alpha; it must equal -K (x - x_k) / dt with K formed
  // explicitly from a separate solver, and take no solve. The first iterate of the next step,
  // predicted from the accepted step's g, is followed the same way.
  Fixture f = makeFixture(17);
  const auto rss = rssWithEps(2e-3, true);
  RssHydrodynamics& e = *rss;
  beginStep(e, f);
  InverseBlockSink sink;
  const ReferenceFrames fr = transportFrames(f.net, f.q, f.start.frames);
  e.addDenseJacobian({f.net, f.q, fr, f.start.q, f.start.qdot, f.dt, f.dt, f.medium, 1.3}, sink);
  ASSERT_NE(sink.matrix, nullptr);
  const auto explicitForce = [&](const RodState& start, const VecX& q) {
    rss::Polyline line;  // every tail chain, segments within a chain only
    rss::Segments segments;
    for (const std::vector<int>& chain : f.net.parts.tail_nodes)
      for (size_t k = 0; k < chain.size(); ++k) {
        if (k > 0)
          segments.push_back({static_cast<int>(line.size()) - 1, static_cast<int>(line.size())});
        line.push_back(nodePosition(start.q, chain[k]));
      }
    const rss::RssSolver separate(line, segments, 2e-3, f.medium.viscosity());
    VecX dx(sink.block_dofs.size());
    for (size_t i = 0; i < sink.block_dofs.size(); ++i)
      dx(i) = q(sink.block_dofs[i]) - start.q(sink.block_dofs[i]);
    const VecX f_h = -separate.dragMatrix() * dx / f.dt;
    VecX F = VecX::Zero(f.net.ndof());
    for (size_t i = 0; i < sink.block_dofs.size(); ++i) F(sink.block_dofs[i]) = f_h(i);
    return F;
  };
  const VecX at_q = forceAt(e, f, f.q);  // not followed yet: solved, then followed
  EXPECT_EQ(e.forceSolves(), 1);
  EXPECT_LT((at_q - explicitForce(f.start, f.q)).norm(), 1e-9 * at_q.norm());
  // A mapped update from the followed iterate
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> u(-1e-4, 1e-4);
  const VecX z = VecX::NullaryExpr(f.net.ndof(), [&] { return u(rng); });
  const double alpha = 0.37 * sink.matrix->matrix().diagonal().cwiseAbs().mean();
  VecX z_h(sink.block_dofs.size());
  for (size_t i = 0; i < sink.block_dofs.size(); ++i) z_h(i) = z(sink.block_dofs[i]);
  const VecX moved = sink.matrix->matrix() * z_h / alpha;
  VecX q_next = f.q - z;
  for (size_t i = 0; i < sink.block_dofs.size(); ++i)
    q_next(sink.block_dofs[i]) = f.q(sink.block_dofs[i]) - moved(i);
  e.noteMappedUpdate(f.q, q_next, z, sink.matrix, alpha);
  const VecX followed = forceAt(e, f, q_next);
  EXPECT_EQ(e.forceSolves(), 1);
  const VecX expected = explicitForce(f.start, q_next);
  ASSERT_GT(expected.norm(), 0.0);
  EXPECT_LT((followed - expected).norm(), 1e-9 * expected.norm());
  // Another matrix's mapping, or an update from an iterate it does not follow, is not followed:
  // the next force is solved again
  LuFactoredMatrix other;
  ASSERT_TRUE(other.factorize(MatX::Identity(3, 3)));
  e.noteMappedUpdate(q_next, f.q, z, &other, alpha);
  EXPECT_LT((forceAt(e, f, f.q) - at_q).norm(), 1e-12 * at_q.norm());
  EXPECT_EQ(e.forceSolves(), 2);
  e.noteMappedUpdate(q_next, f.q, z, sink.matrix, alpha);  // it follows f.q, not q_next
  EXPECT_LT((forceAt(e, f, f.q) - at_q).norm(), 1e-12 * at_q.norm());
  EXPECT_EQ(e.forceSolves(), 3);
  // Accept the step at q_next, start the next one there: the predicted first iterate is followed
  RodState end = f.start;
  end.time = f.start.time + f.dt;
  end.q = q_next;
  end.frames = transportFrames(f.net, q_next, f.start.frames);
  e.acceptStep(f.net, f.start, end);
  const long solves = e.forceSolves();
  e.beginStep({f.net, end, f.dt, f.medium, f.medium.viscosity()});
  VecX predicted = end.q + f.dt * (end.q - f.start.q);
  e.predictIterate(end, f.dt, predicted);
  VecX F = VecX::Zero(f.net.ndof());
  const ReferenceFrames fr2 = transportFrames(f.net, predicted, end.frames);
  e.addForce({f.net, predicted, fr2, end.q, end.qdot, f.dt, end.time + f.dt, f.medium,
              f.medium.viscosity()},
             F, nullptr);
  EXPECT_EQ(e.forceSolves(), solves);
  const VecX expected_next = explicitForce(end, predicted);
  EXPECT_LT((F - expected_next).norm(), 1e-9 * expected_next.norm());
}

TEST(RssEffect, BadViscosityAndEmptyRobotAreReported) {
  const auto rss = rssWithEps(2e-3, true);
  RssHydrodynamics& e = *rss;
  RodNetwork rod = testing::makeStraightRod(4, 0.02, testing::vpsMaterial());
  EXPECT_THROW(e.attach(rod), ConfigError);  // no tail chains
  Fixture f = makeFixture(9);
  e.attach(f.net);
  EXPECT_THROW(e.beginStep({f.net, f.start, f.dt, f.medium, 0.0}), std::runtime_error);
}

TEST(RssEffect, EpsRatioTimesFilamentRadiusOrEpsWhicheverWasSetLast) {
  const Fixture f = makeFixture(10);
  RssHydrodynamics relative(2e-3, true);  // r0 = 2 mm, eps = eps_ratio r0
  relative.parameters().set("eps_ratio", 1.2);
  beginStep(relative, f);
  EXPECT_DOUBLE_EQ(relative.parameters().get("eps"), 2.4e-3);
  const auto fixed = rssWithEps(2.4e-3, true);
  beginStep(*fixed, f);
  EXPECT_EQ(forceAt(relative, f, f.q), forceAt(*fixed, f, f.q));
  relative.parameters().set("eps", 3e-3);  // a running session sets eps: it wins from now on
  beginStep(relative, f);
  const auto fixed3 = rssWithEps(3e-3, true);
  beginStep(*fixed3, f);
  EXPECT_EQ(forceAt(relative, f, f.q), forceAt(*fixed3, f, f.q));
  relative.parameters().set("eps_ratio", 1.0);  // and eps_ratio again after it
  beginStep(relative, f);
  EXPECT_DOUBLE_EQ(relative.parameters().get("eps"), 2e-3);
  // a config may give one of the two, not both
  EffectSpec spec{"rss", {{"coupling", "implicit"}}, {{"eps", 2e-3}, {"eps_ratio", 1.0}}};
  RobotDimensions robot;
  const std::string message =
      testing::errorMessageOf<ConfigError>([&] { makeEffect(spec, f.medium, robot); });
  EXPECT_NE(message.find("effects.rss: give eps or eps_ratio, not both"), std::string::npos)
      << message;
}

// ---- a stiff rod sedimenting broadside under a uniform load ------------------------------------

struct Sediment {
  Vec3 velocity;    ///< mean node velocity at the end
  Vec3 hydro;       ///< total hydrodynamic force at the end
  Vec3 load;        ///< total applied load
  double drag = 0;  ///< rigid broadside drag coefficient of the rod from RssSolver [N s/m]
  int factorizations = 0;
  int newton_iterations = 0;
};

Sediment sediment(bool implicit, double dt, double duration,
                  double jacobian_reuse = NewtonOptions().jacobian_reuse,
                  int krylov_iterations = NewtonOptions().krylov_iterations,
                  bool condensed_dense_lu = NewtonOptions().condensed_dense_lu) {
  RodMaterial m = testing::vpsMaterial();
  m.radius = 1e-3;
  m.youngs_modulus = 1e9;  // nearly rigid: the result is compared with a rigid rod
  RodNetwork rod = testing::makeStraightRod(20, 0.1, m);
  std::vector<int> chain;
  std::vector<int> edges;
  for (int i = 0; i < rod.numNodes(); ++i) chain.push_back(i);
  for (int j = 0; j < rod.numEdges(); ++j) edges.push_back(j);
  rod.parts.tail_nodes = {chain};
  rod.parts.tail_edges = {edges};
  rod.parts.motor_spring = -1;
  const double eps = 1.65e-3;
  EffectPtr rss = rssWithEps(eps, implicit);
  auto load = std::make_unique<ConstantLoad>();
  const Vec3 per_node(2e-4, 0.0, 0.0);
  for (int i = 0; i < rod.numNodes(); ++i) load->addNodeForce(i, per_node);
  std::vector<EffectPtr> effects;
  effects.push_back(std::move(rss));
  effects.push_back(std::move(load));
  Medium medium;
  medium.parameters().set("viscosity", 1.0);
  NewtonOptions options;
  options.force_scale = 1e-4;
  options.moment_scale = 1e-5;
  options.length_scale = 0.1;
  options.jacobian_reuse = jacobian_reuse;
  options.krylov_iterations = krylov_iterations;
  options.condensed_dense_lu = condensed_dense_lu;
  ImplicitStepper stepper(rod, std::move(effects), medium, options);
  EXPECT_EQ(stepper.denseLinearSolve(), implicit);
  RodState s = stepper.initialState();
  ConstantMotor motor(0.0);
  const long steps = std::lround(duration / dt);
  Sediment out;
  for (long k = 0; k < steps; ++k)
    out.newton_iterations += stepper.step(s, dt, motor).newton_iterations;
  out.factorizations = stepper.totalFactorizations();
  out.velocity.setZero();
  for (int i = 0; i < rod.numNodes(); ++i) out.velocity += s.qdot.segment<3>(3 * i);
  out.velocity /= rod.numNodes();
  // Total hydrodynamic force at the end state, through the effect itself.
  const Effect* e = stepper.findEffect("rss");
  const auto probe_rss = rssWithEps(eps, true);
  RssHydrodynamics& probe = *probe_rss;
  probe.attach(rod);
  RodState previous = s;
  previous.q = s.q - dt * s.qdot;
  probe.beginStep({rod, previous, dt, medium, 1.0});
  VecX F = VecX::Zero(rod.ndof());
  probe.addForce({rod, s.q, s.frames, previous.q, s.qdot, dt, s.time, medium, 1.0}, F, nullptr);
  out.hydro.setZero();
  for (int i = 0; i < rod.numNodes(); ++i) out.hydro += F.segment<3>(3 * i);
  out.load = per_node * rod.numNodes();
  rss::Polyline line;
  for (int i = 0; i < rod.numNodes(); ++i) line.push_back(nodePosition(s.q, i));
  const MatX K = rss::RssSolver(line, eps, 1.0).dragMatrix();
  VecX U = VecX::Zero(3 * rod.numNodes());
  for (int i = 0; i < rod.numNodes(); ++i) U(3 * i) = 1.0;
  const VecX f = K * U;
  for (int i = 0; i < rod.numNodes(); ++i) out.drag += f(3 * i);
  EXPECT_NE(e, nullptr);
  return out;
}

TEST(RssEffect, SedimentingRodBalancesLoadInEveryOption) {
  const Sediment b = sediment(true, 1e-3, 0.05);
  // Zero Reynolds number: the hydrodynamic force balances the load.
  EXPECT_LT((b.hydro + b.load).norm(), 1e-3 * b.load.norm());
  // A nearly rigid rod: the speed is load / rigid broadside drag.
  EXPECT_NEAR(b.velocity.x(), b.load.x() / b.drag, 5e-3 * b.velocity.x());
  EXPECT_LT(std::abs(b.velocity.y()) + std::abs(b.velocity.z()), 1e-6 * b.velocity.x());
  // Option A (explicit) at a small step agrees with option B.
  const Sediment a = sediment(false, 1e-4, 0.05);
  EXPECT_NEAR(a.velocity.x(), b.velocity.x(), 2e-3 * b.velocity.x());
  // Option B is stable and converged at a step 10x larger than the relaxation time.
  const Sediment big = sediment(true, 2e-2, 0.2);
  EXPECT_NEAR(big.velocity.x(), b.velocity.x(), 2e-3 * b.velocity.x());
}

TEST(RssEffect, ChordStepsReuseTheDenseJacobianWithoutChangingTheAnswer) {
  // NewtonOptions::jacobian_reuse: the factorised Jacobian serves later updates while
  // Newton contracts; the same residual test decides convergence, so the balance law holds and
  // the answer matches refactoring every iteration.
  const Sediment fresh = sediment(true, 1e-3, 0.05, 0.0, 0);
  const Sediment reused = sediment(true, 1e-3, 0.05, NewtonOptions().jacobian_reuse, 0);
  EXPECT_LT((reused.hydro + reused.load).norm(), 1e-3 * reused.load.norm());
  EXPECT_NEAR(reused.velocity.x(), fresh.velocity.x(), 1e-4 * fresh.velocity.x());
  EXPECT_LT(reused.factorizations, fresh.factorizations);
  RecordProperty("factorizations_fresh", fresh.factorizations);
  RecordProperty("factorizations_reused", reused.factorizations);
}

TEST(RssEffect, KrylovUpdatesKeepOneFactorizationWithoutChangingTheAnswer) {
  // NewtonOptions::krylov_iterations: GMRES on the Jacobian at each iterate, preconditioned by a
  // factorisation kept across steps; the same residual test decides convergence, so the balance
  // law holds and the answer matches a factorisation at every iterate.
  const Sediment fresh = sediment(true, 1e-3, 0.05, 0.0, 0);
  const Sediment krylov = sediment(true, 1e-3, 0.05, 0.0);
  EXPECT_LT((krylov.hydro + krylov.load).norm(), 1e-3 * krylov.load.norm());
  EXPECT_NEAR(krylov.velocity.x(), fresh.velocity.x(), 1e-4 * fresh.velocity.x());
  EXPECT_LT(krylov.factorizations, fresh.factorizations / 10);
  RecordProperty("factorizations_fresh", fresh.factorizations);
  RecordProperty("factorizations_krylov", krylov.factorizations);
}

TEST(RssEffect, CondensedDenseLuGivesTheWholeMatrixAnswer) {
  // NewtonOptions::condensed_dense_lu: the twist DOFs condensed out and the Schur complement on
  // the RSS nodes factored solve the same Newton systems as a dense LU of the whole Jacobian, so
  // the steps agree to round-off, with Newton-Krylov updates and with a factorisation per update.
  for (int krylov : {0, NewtonOptions().krylov_iterations}) {
    SCOPED_TRACE("krylov_iterations " + std::to_string(krylov));
    const Sediment whole = sediment(true, 1e-3, 0.05, 0.0, krylov, false);
    const Sediment condensed = sediment(true, 1e-3, 0.05, 0.0, krylov, true);
    EXPECT_LT((condensed.velocity - whole.velocity).norm(), 1e-9 * whole.velocity.norm());
    EXPECT_EQ(condensed.newton_iterations, whole.newton_iterations);
  }
}

}  // namespace
}  // namespace flagella
