// The 4x4-block sparse LU (solver/block_sparse_lu.h) and its KLU fallback (JacobianSolver):
// solutions checked by their residual A x - b and against a dense LU, on random non-symmetric
// matrices with a robot's Jacobian pattern and with patterns that fill in; a singular pivot
// block falls back to KLU; the stepper gives the same trajectory with either solver.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "flagella_sim/core/sparse_assembler.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/robots/multi_tail_robot.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "flagella_sim/solver/block_sparse_lu.h"
#include "flagella_sim/solver/jacobian_solver.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
// Backward-stable solves of these well-conditioned systems leave a relative residual of a few
// machine epsilons times the dimension; this bound is far above that and far below any error.
constexpr double kRelativeResidualTol = 1e-12;

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

using Triplets = std::vector<Eigen::Triplet<double>>;

// Random non-symmetric values on a symmetric pattern given as lists of coupled DOFs (every pair
// in a list coupled), with a diagonal shift so that the matrix is comfortably non-singular.
SparseMatrix randomMatrix(int n, const std::vector<std::vector<int>>& cliques, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Triplets t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 4.0 + value(rng));
  for (const std::vector<int>& clique : cliques)
    for (int a : clique)
      for (int b : clique) t.emplace_back(a, b, value(rng));
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// The elastic Hessian's pattern of a network: DOFs coupled by each stretching spring (two nodes)
// and each bending-twisting spring (three nodes, two twists), docs/model.md 1.2.
std::vector<std::vector<int>> springCliques(const RodNetwork& net) {
  std::vector<std::vector<int>> cliques;
  auto coordinates = [](std::vector<int>& c, int node) {
    for (int a = 0; a < 3; ++a) c.push_back(RodNetwork::positionIndex(node) + a);
  };
  for (const StretchSpring& s : net.stretch_springs) {
    std::vector<int> c;
    coordinates(c, net.edges[s.edge].start_node);
    coordinates(c, net.edges[s.edge].end_node);
    cliques.push_back(c);
  }
  for (const BendTwistSpring& s : net.bend_twist_springs) {
    std::vector<int> c;
    for (int node : {s.node_p, s.node_c, s.node_q}) coordinates(c, node);
    c.push_back(net.thetaIndex(s.edge_e));
    c.push_back(net.thetaIndex(s.edge_f));
    cliques.push_back(c);
  }
  return cliques;
}

double relativeResidual(const SparseMatrix& A, const VecX& x, const VecX& b) {
  return (A * x - b).norm() / (b.norm() + 1e-300);
}

VecX randomVector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  VecX v(n);
  for (int i = 0; i < n; ++i) v(i) = value(rng);
  return v;
}

void expectSolves(const SparseMatrix& A, const std::vector<BlockSparseLu::DofGroup>& groups,
                  unsigned seed) {
  BlockSparseLu lu;
  lu.analyze(A, groups);
  ASSERT_TRUE(lu.factorize(A, 1e-13));
  for (unsigned k = 0; k < 3; ++k) {
    const VecX b = randomVector(static_cast<int>(A.rows()), seed + k);
    const VecX x = lu.solve(b);
    EXPECT_LT(relativeResidual(A, x, b), kRelativeResidualTol);
    const VecX dense = Eigen::MatrixXd(A).partialPivLu().solve(b);
    EXPECT_LT((x - dense).norm(), 1e-10 * dense.norm());
  }
}

TEST(BlockSparseLu, SolvesRandomSystemsWithTheRobotsPatterns) {
  for (const char* name : {"granular_design1.yaml", "interface_robot.yaml", "helical_robot.yaml"}) {
    SCOPED_TRACE(name);
    const std::vector<std::string> three_tails{"robot.n_tails=3"};
    const bool helical = std::string(name).rfind("helical", 0) == 0;
    Simulation sim(loadSimulationConfig(shippedConfig(name),
                                        helical ? std::vector<std::string>{} : three_tails));
    const RodNetwork& net = sim.stepper().network();
    const SparseMatrix A = randomMatrix(net.ndof(), springCliques(net), 7);
    const std::vector<BlockSparseLu::DofGroup> groups = nodeEdgeBlocks(net);
    expectSolves(A, groups, 11);
    BlockSparseLu lu;
    lu.analyze(A, groups);
    EXPECT_EQ(lu.fillBlocks(), 0) << "a tree-shaped network eliminates without fill";
    // Refactorisation with new values on the same pattern.
    const SparseMatrix B = randomMatrix(net.ndof(), springCliques(net), 8);
    ASSERT_TRUE(lu.factorize(B, 1e-13));
    const VecX b = randomVector(net.ndof(), 3);
    EXPECT_LT(relativeResidual(B, lu.solve(b), b), kRelativeResidualTol);
  }
}

TEST(BlockSparseLu, PatternsThatFillInAndUnevenGroups) {
  // A ring of 12 blocks of 1-4 DOFs with random chords: elimination creates fill blocks.
  const std::vector<int> sizes{4, 1, 3, 2, 4, 4, 1, 2, 3, 4, 2, 1};
  std::vector<BlockSparseLu::DofGroup> groups;
  std::vector<std::vector<int>> members;
  int n = 0;
  for (int size : sizes) {
    BlockSparseLu::DofGroup g{-1, -1, -1, -1};
    std::vector<int> m;
    for (int s = 0; s < size; ++s) {
      g[s] = n;
      m.push_back(n++);
    }
    groups.push_back(g);
    members.push_back(m);
  }
  std::vector<std::vector<int>> cliques;
  auto couple = [&](int i, int j) {
    std::vector<int> c = members[i];
    c.insert(c.end(), members[j].begin(), members[j].end());
    cliques.push_back(c);
  };
  const int nb = static_cast<int>(sizes.size());
  for (int i = 0; i < nb; ++i) couple(i, (i + 1) % nb);
  couple(0, 6);
  couple(3, 9);
  couple(2, 10);
  const SparseMatrix A = randomMatrix(n, cliques, 5);
  BlockSparseLu lu;
  lu.analyze(A, groups);
  EXPECT_GT(lu.fillBlocks(), 0);
  expectSolves(A, groups, 21);
}

TEST(BlockSparseLu, RefusesASingularPivotBlockAndKluTakesOver) {
  // Two blocks coupled as [[0, I], [I, D]]: the first diagonal block is zero, the matrix is not
  // singular. The block LU must refuse; JacobianSolver then solves it by KLU's pivoting.
  Triplets t;
  for (int a = 0; a < 4; ++a) {
    t.emplace_back(a, 4 + a, 1.0);
    t.emplace_back(4 + a, a, 1.0);
    t.emplace_back(4 + a, 4 + a, 2.0 + a);
  }
  SparseMatrix A(8, 8);
  A.setFromTriplets(t.begin(), t.end());
  const std::vector<BlockSparseLu::DofGroup> groups{{0, 1, 2, 3}, {4, 5, 6, 7}};
  BlockSparseLu lu;
  lu.analyze(A, groups);
  EXPECT_FALSE(lu.factorize(A, 1e-13));

  JacobianSolver solver;
  solver.setBlocks(groups);
  solver.analyze(A);
  ASSERT_TRUE(solver.factorize(A));
  EXPECT_EQ(solver.blockFallbacks(), 1);
  EXPECT_EQ(solver.blockFactorizations(), 0);
  const VecX b = randomVector(8, 1);
  EXPECT_LT(relativeResidual(A, solver.solve(b), b), kRelativeResidualTol);
}

TEST(BlockSparseLu, TinyPivotRatioIsRefused) {
  Triplets t{{0, 0, 1.0}, {1, 1, 1e-15}};
  SparseMatrix A(2, 2);
  A.setFromTriplets(t.begin(), t.end());
  BlockSparseLu lu;
  lu.analyze(A, {{0, -1, -1, -1}, {1, -1, -1, -1}});
  EXPECT_FALSE(lu.factorize(A, 1e-13));
  EXPECT_TRUE(lu.factorize(A, 1e-16));
  // The ratio is among the matrix's own pivots: the padding's unit pivots do not count, so a
  // matrix in units that make every entry tiny is accepted.
  const SparseMatrix tiny = 1e-20 * A.cwiseAbs().cwiseSign();
  EXPECT_TRUE(lu.factorize(tiny, 1e-13));
  const VecX b = VecX::Constant(2, 1e-20);
  EXPECT_LT(relativeResidual(tiny, lu.solve(b), b), kRelativeResidualTol);
}

TEST(BlockSparseLu, GroupsMustCoverEveryDofOnce) {
  SparseMatrix A(3, 3);
  A.setIdentity();
  BlockSparseLu lu;
  EXPECT_THROW(lu.analyze(A, {{0, 1, -1, -1}}), std::invalid_argument);  // DOF 2 missing
  EXPECT_THROW(lu.analyze(A, {{0, 1, 2, -1}, {2, -1, -1, -1}}), std::invalid_argument);  // twice
  EXPECT_THROW(lu.analyze(A, {{0, 1, 2, 3}}), std::invalid_argument);  // out of range
}

TEST(BlockSparseLu, NodeEdgeBlocksCoverEveryDofOnce) {
  for (const char* name : {"granular_design1.yaml", "interface_robot.yaml", "helical_robot.yaml"}) {
    SCOPED_TRACE(name);
    Simulation sim(loadSimulationConfig(shippedConfig(name)));
    const RodNetwork& net = sim.stepper().network();
    std::vector<int> seen(net.ndof(), 0);
    for (const BlockSparseLu::DofGroup& g : nodeEdgeBlocks(net))
      for (int dof : g)
        if (dof >= 0) ++seen.at(dof);
    for (int dof = 0; dof < net.ndof(); ++dof) EXPECT_EQ(seen[dof], 1) << "DOF " << dof;
  }
}

// One pass of a robot's Jacobian-shaped contributions with random values (the stepper's calls:
// entries one by one, 3x3 blocks, 11x11 spring blocks), the same sequence for every seed.
void assembleRandom(SparseAssembler& a, const RodNetwork& net, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  a.begin();
  for (int i = 0; i < net.ndof(); ++i) a.add(i, i, 10.0 + value(rng));
  for (const StretchSpring& s : net.stretch_springs) {
    const int p = RodNetwork::positionIndex(net.edges[s.edge].start_node);
    const int q = RodNetwork::positionIndex(net.edges[s.edge].end_node);
    for (int row : {p, q})
      for (int col : {p, q}) a.addBlock(row, col, Mat3::NullaryExpr([&] { return value(rng); }));
  }
  for (const BendTwistSpring& s : net.bend_twist_springs) {
    const SpringDofMap map = springDofMap(net, s);
    a.addDense<11>(map.index, SpringMatrix::NullaryExpr([&] { return value(rng); }));
  }
  for (int i = 0; i + 1 < net.ndof(); i += 7) a.add(i + 1, i, value(rng));  // single entries
}

// Assembly in place: a pass redirected into the block LU's storage factors to the same LU as
// the assembled matrix copied in (bit for bit: the same sums in the same order); a redirected
// pass whose contributions differ returns to the matrix with every value in it.
TEST(BlockSparseLu, AssemblyInPlaceMatchesTheCopiedMatrix) {
  Simulation sim(loadSimulationConfig(shippedConfig("granular_design1.yaml"), {"robot.n_tails=3"}));
  const RodNetwork& net = sim.stepper().network();
  SparseAssembler a(net.ndof());
  assembleRandom(a, net, 1);
  BlockSparseLu lu;
  lu.analyze(a.finish(), nodeEdgeBlocks(net));
  assembleRandom(a, net, 2);
  const SparseMatrix copied = a.finish();
  EXPECT_FALSE(a.patternChanged());
  ASSERT_TRUE(lu.factorize(copied, 1e-13));
  const VecX b = randomVector(net.ndof(), 7);
  const VecX x_copied = lu.solve(b);
  EXPECT_LT(relativeResidual(copied, x_copied, b), kRelativeResidualTol);

  a.redirect(lu.storage(), lu.storageSize(), lu.valueOffsets());
  lu.clearStorage();
  assembleRandom(a, net, 2);
  a.finish();
  EXPECT_FALSE(a.patternChanged());
  EXPECT_TRUE(a.redirected());
  ASSERT_TRUE(lu.factorizeInPlace(1e-13));
  EXPECT_EQ((lu.solve(b) - x_copied).cwiseAbs().maxCoeff(), 0.0);

  // One contribution more, at an entry outside the pattern, in the middle of a redirected pass.
  lu.clearStorage();
  SparseAssembler fresh(net.ndof());
  for (SparseAssembler* target : {&a, &fresh}) {
    assembleRandom(*target, net, 3);
    target->add(0, net.ndof() - 1, 0.5);
  }
  const SparseMatrix& changed = a.finish();
  EXPECT_TRUE(a.patternChanged());
  EXPECT_FALSE(a.redirected());
  EXPECT_EQ(SparseMatrix(changed - fresh.finish()).norm(), 0.0);
}

// The block LU refuses a Jacobian assembled in its storage: JacobianSolver reports it, and the
// same values assembled as a matrix are factored by KLU alone.
TEST(BlockSparseLu, RefusalInPlaceLeavesTheMatrixToKlu) {
  // [[d I, I], [I, D]]: d = 1 first (accepted), then d = 0 (a zero pivot block).
  auto assemble = [](SparseAssembler& a, double d) {
    a.begin();
    for (int k = 0; k < 4; ++k) {
      a.add(k, k, d);
      a.add(k, 4 + k, 1.0);
      a.add(4 + k, k, 1.0);
      a.add(4 + k, 4 + k, 2.0 + k);
    }
  };
  const std::vector<BlockSparseLu::DofGroup> groups{{0, 1, 2, 3}, {4, 5, 6, 7}};
  SparseAssembler a(8);
  assemble(a, 1.0);
  JacobianSolver solver;
  solver.setBlocks(groups);
  solver.analyze(a.finish());
  ASSERT_TRUE(solver.factorize(a.matrix()));
  ASSERT_TRUE(solver.lastWasBlock());
  BlockSparseLu& block = solver.blockLu();
  a.redirect(block.storage(), block.storageSize(), block.valueOffsets());
  block.clearStorage();
  assemble(a, 0.0);
  a.finish();
  EXPECT_FALSE(solver.factorizeInPlace());
  EXPECT_EQ(solver.blockFallbacks(), 1);
  a.stopRedirect();
  assemble(a, 0.0);
  const SparseMatrix& A = a.finish();
  ASSERT_TRUE(solver.factorize(A, false));
  EXPECT_FALSE(solver.lastWasBlock());
  EXPECT_EQ(solver.blockFallbacks(), 1);  // KLU alone: the block LU was not tried again
  const VecX b = randomVector(8, 3);
  EXPECT_LT(relativeResidual(A, solver.solve(b), b), kRelativeResidualTol);
}

// A stiff anchor on one coordinate, F = -k (x - x(t_k)), whose Jacobian entry is in the pattern
// from the start and switched on at on_time: a jump in the Jacobian's pivot ratio mid-run.
// [N/m]: against the robot's mass and elastic pivots, a pivot ratio the block LU refuses
constexpr double kAnchorStiffness = 1e12;
class SwitchedAnchor : public Effect, public ForceLaw {
 public:
  SwitchedAnchor(int dof, double on_time, double stiffness)
      : Effect("switched_anchor"), dof_(dof), on_time_(on_time), stiffness_(stiffness) {}
  void addForce(const EffectContext& ctx, VecX& force, JacobianSink* jacobian) const override {
    const double k = ctx.time > on_time_ ? stiffness_ : 0.0;
    force(dof_) -= k * (ctx.q(dof_) - ctx.q_start(dof_));
    if (jacobian) jacobian->add(dof_, dof_, -k);
  }

 private:
  int dof_;
  double on_time_, stiffness_;
};

// The block LU refuses a Jacobian assembled in its storage in the middle of a run: the step is
// completed by KLU (the Jacobian assembled again as a matrix), and the run matches a KLU-only
// run of the same robot.
TEST(BlockSparseLu, StepperFallsBackToKluWhenRefusedInPlace) {
  const SimulationConfig config = loadSimulationConfig(shippedConfig("granular_design1.yaml"));
  auto run = [&](bool block_lu, int steps, int* fallbacks, int* substeps) {
    NewtonOptions options = config.solver;
    options.block_lu = block_lu;
    std::vector<EffectPtr> effects;
    for (const EffectSpec& spec : config.effects)
      effects.push_back(makeEffect(spec, config.medium, config.robotDimensions()));
    const RodNetwork net = config.robot->build();
    const int tip = RodNetwork::positionIndex(net.parts.tail_nodes.front().back());
    effects.push_back(std::make_unique<SwitchedAnchor>(tip, 5.5 * config.dt, kAnchorStiffness));
    ImplicitStepper stepper(net, std::move(effects), config.medium, options);
    RodState state = stepper.initialState();
    const std::shared_ptr<const MotorCommand> command = makeMotor(config.motor);
    for (int k = 0; k < steps; ++k) *substeps += stepper.step(state, config.dt, *command).substeps;
    *fallbacks = stepper.linearSolver().blockFallbacks();
    return state;
  };
  constexpr int kSteps = 10;
  int block_fallbacks = 0, klu_fallbacks = 0, block_substeps = 0, klu_substeps = 0;
  const RodState a = run(true, kSteps, &block_fallbacks, &block_substeps);
  const RodState b = run(false, kSteps, &klu_fallbacks, &klu_substeps);
  EXPECT_GT(block_fallbacks, 0);
  EXPECT_EQ(block_substeps, kSteps);  // the refused step is not subdivided: KLU completes it
  EXPECT_EQ(klu_substeps, kSteps);
  const double scale = a.q.cwiseAbs().maxCoeff();
  EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-9 * std::max(scale, 1.0));
}

// The stepper's trajectory does not depend on which LU solves the Newton system: both solve it
// to round-off, so the states after a second of motion agree far inside the Newton tolerance.
TEST(BlockSparseLu, SameTrajectoryAsKlu) {
  for (const char* name : {"granular_design1.yaml", "interface_robot.yaml"}) {
    SCOPED_TRACE(name);
    SimulationConfig block = loadSimulationConfig(shippedConfig(name), {"robot.n_tails=3"});
    SimulationConfig klu = block;
    klu.solver.block_lu = false;
    Simulation a(block), b(klu);
    int iterations_a = 0, iterations_b = 0;
    for (int k = 0; k < 100; ++k) {
      iterations_a += a.step().newton_iterations;
      iterations_b += b.step().newton_iterations;
    }
    EXPECT_EQ(iterations_a, iterations_b);
    const double scale =
        a.state().q.head(3 * a.stepper().network().numNodes()).cwiseAbs().maxCoeff();
    EXPECT_LT((a.state().q - b.state().q).cwiseAbs().maxCoeff(), 1e-9 * std::max(scale, 1.0));
    EXPECT_EQ(a.stepper().linearSolver().blockFallbacks(), 0);
    EXPECT_GT(a.stepper().linearSolver().blockFactorizations(), 0);
    EXPECT_EQ(b.stepper().linearSolver().blockFactorizations(), 0);
  }
}

}  // namespace
}  // namespace flagella
