// The 4x4-block sparse LU (solver/block_sparse_lu.h) and its KLU fallback (JacobianSolver):
// solutions checked by their residual A x - b and against a dense LU, on random non-symmetric
// matrices with a robot's Jacobian pattern and with patterns that fill in; a singular pivot
// block falls back to KLU; the stepper gives the same trajectory with either solver.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>
#include <string>
#include <vector>

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
