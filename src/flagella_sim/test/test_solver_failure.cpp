// Tests of the implicit stepper's failure handling: a step that cannot be solved throws
// SolverFailure and leaves the state exactly as it was; a step that fails whole but succeeds in
// halves is completed by subdivision; a non-finite motor command is a SolverFailure; and the
// sparse symbolic analysis is done once and reused across iterations and steps.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/robots/multi_tail_robot.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr char kDesign1[] = "granular_design1.yaml";
constexpr char kInterfaceRobot[] = "interface_robot.yaml";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTimeTol = 1e-12;  // [s]
// Two Newton solutions of the same step that differ only in LU pivot history agree to far
// better than this [m or rad].
constexpr double kSameSolutionTol = 1e-9;
constexpr int kWarmupSteps = 5;
constexpr int kManySteps = 150;

// Overrides that make every Newton solve impossible: one update cannot reach 1e-10.
const std::vector<std::string> kImpossibleSolver{
    "solver.max_iterations=1", "solver.residual_tolerance=1e-10", "solver.max_subdivision_depth=2"};

// A 0.2 s step at 1000 rpm without soft start: Newton fails on the whole step but converges on
// the halves (found by scanning dt and omega_T for design 1).
constexpr double kBigDt = 0.2;
const std::vector<std::string> kNeedsSubdivision{"simulation.dt=0.2",
                                                 "simulation.output_interval=0.2",
                                                 "motor.omega_rpm=1000", "motor.ramp_time=0"};

// A 1 s step at 5000 rpm: not solvable even with the default 6 subdivisions.
const std::vector<std::string> kHugeStep{"simulation.dt=1", "simulation.output_interval=1",
                                         "motor.omega_rpm=5000", "motor.ramp_time=0"};

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

SimulationConfig design1(const std::vector<std::string>& overrides = {}) {
  return loadSimulationConfig(shippedConfig(kDesign1), overrides);
}

ImplicitStepper makeStepper(const SimulationConfig& c) {
  std::vector<EffectPtr> effects;
  for (const EffectSpec& spec : c.effects)
    effects.push_back(makeEffect(spec, c.medium, c.robotDimensions()));
  return ImplicitStepper(c.robot->build(), std::move(effects), c.medium, c.solver);
}

bool allFinite(const RodState& s) {
  if (!std::isfinite(s.time) || !s.q.allFinite() || !s.qdot.allFinite() ||
      !std::isfinite(s.motor_twist_offset))
    return false;
  for (const auto* list : {&s.frames.tangent, &s.frames.d1, &s.frames.d2})
    for (const Vec3& v : *list)
      if (!v.allFinite()) return false;
  for (double m : s.frames.reference_twist)
    if (!std::isfinite(m)) return false;
  return true;
}

bool sameVectors(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) return false;
  return true;
}

/// Bit-for-bit equality of two states (a failed step must not touch anything).
::testing::AssertionResult identical(const RodState& a, const RodState& b) {
  if (a.time != b.time)
    return ::testing::AssertionFailure() << "time " << a.time << " vs " << b.time;
  if (a.q.size() != b.q.size() || a.q != b.q) return ::testing::AssertionFailure() << "q differs";
  if (a.qdot.size() != b.qdot.size() || a.qdot != b.qdot)
    return ::testing::AssertionFailure() << "qdot differs";
  if (a.motor_twist_offset != b.motor_twist_offset)
    return ::testing::AssertionFailure() << "motor_twist_offset differs";
  if (!sameVectors(a.frames.tangent, b.frames.tangent) || !sameVectors(a.frames.d1, b.frames.d1) ||
      !sameVectors(a.frames.d2, b.frames.d2) ||
      a.frames.reference_twist != b.frames.reference_twist)
    return ::testing::AssertionFailure() << "reference frames differ";
  return ::testing::AssertionSuccess();
}

std::string solverFailureOf(const std::function<void()>& fn) {
  return testing::errorMessageOf<SolverFailure>(fn);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

double motorTauBar(const ImplicitStepper& stepper) {
  const RodNetwork& net = stepper.network();
  return net.bend_twist_springs.at(net.parts.motor_spring).tau_bar;
}

// ---------------------------------------------------------------------------------------------
// (a) Impossible solves
// ---------------------------------------------------------------------------------------------

TEST(SolverFailure, ImpossibleSolveThrowsAndLeavesSimulationUnchanged) {
  Simulation sim(design1(kImpossibleSolver));
  const RodState before = sim.state();
  const size_t samples_before = sim.trajectory().size();
  const std::string msg = solverFailureOf([&] { sim.step(); });
  EXPECT_TRUE(identical(sim.state(), before));
  EXPECT_EQ(sim.time(), 0.0);
  EXPECT_EQ(sim.trajectory().size(), samples_before);
  EXPECT_TRUE(allFinite(sim.state()));
  EXPECT_TRUE(contains(msg, "t = 0")) << msg;
  EXPECT_TRUE(contains(msg, "dt = ")) << msg;
  EXPECT_TRUE(contains(msg, "tolerance")) << msg;
  // Deterministic: the same failure again, state still untouched.
  EXPECT_EQ(solverFailureOf([&] { sim.step(); }), msg);
  EXPECT_TRUE(identical(sim.state(), before));
}

TEST(SolverFailure, AJointFoldedBackOnItselfIsNamed) {
  // A tail joint folded to 179.5 deg, where the discrete curvature diverges (docs/model.md 1.3):
  // the failure message names the joint and its angle; an unfolded robot's does not.
  const SimulationConfig c = design1(kImpossibleSolver);
  ImplicitStepper stepper = makeStepper(c);
  const RodNetwork& net = stepper.network();
  RodState s = stepper.initialState();
  ConstantMotor motor(10.0);  // [rad/s]: a step to take
  const std::string plain = solverFailureOf([&] { stepper.step(s, c.dt, motor); });
  EXPECT_FALSE(contains(plain, "folded")) << plain;
  const int last = static_cast<int>(net.bend_twist_springs.size()) - 1;
  const BendTwistSpring& b = net.bend_twist_springs.at(last);  // a joint near a tail's tip
  const Vec3 xp = nodePosition(s.q, b.node_p), xc = nodePosition(s.q, b.node_c);
  const Vec3 back = (xp - xc).normalized();
  const Vec3 side = back.unitOrthogonal();
  const double angle = 0.5 * M_PI / 180.0;  // 179.5 deg from straight on
  const Vec3 xq = xc + (nodePosition(s.q, b.node_q) - xc).norm() *
                           (std::cos(angle) * back + std::sin(angle) * side);
  s.q.segment<3>(RodNetwork::positionIndex(b.node_q)) = xq;
  s.frames = initialFrames(net, s.q);
  const std::string folded = solverFailureOf([&] { stepper.step(s, c.dt, motor); });
  EXPECT_TRUE(contains(folded, "the joint at node " + std::to_string(b.node_c))) << folded;
  EXPECT_TRUE(contains(folded, "is folded to 179.5")) << folded;
}

TEST(SolverFailure, FailureAfterGoodStepsNamesTheTimeAndKeepsTheLastState) {
  const SimulationConfig c = design1();
  ImplicitStepper stepper = makeStepper(c);
  const ConstantMotor motor(c.motor.omega);
  RodState state = stepper.initialState();
  for (int k = 0; k < kWarmupSteps; ++k) stepper.step(state, c.dt, motor);
  ASSERT_NEAR(state.time, kWarmupSteps * c.dt, kTimeTol);
  const RodState before = state;

  const NewtonOptions good = stepper.options();
  stepper.options().max_iterations = 1;
  stepper.options().residual_tolerance = 1e-14;
  stepper.options().max_subdivision_depth = 2;
  const std::string msg = solverFailureOf([&] { stepper.step(state, c.dt, motor); });
  EXPECT_TRUE(identical(state, before));
  EXPECT_TRUE(allFinite(state));
  EXPECT_TRUE(contains(msg, "t = 0.05")) << msg;
  EXPECT_TRUE(contains(msg, "dt = ")) << msg;

  // Nothing hidden was corrupted: with the good options the step matches a stepper that never
  // failed.
  stepper.options() = good;
  ImplicitStepper reference = makeStepper(c);
  RodState reference_state = stepper.initialState();
  for (int k = 0; k < kWarmupSteps; ++k) reference.step(reference_state, c.dt, motor);
  ASSERT_TRUE(identical(reference_state, before));
  stepper.step(state, c.dt, motor);
  reference.step(reference_state, c.dt, motor);
  EXPECT_NEAR(state.time, reference_state.time, kTimeTol);
  EXPECT_LT((state.q - reference_state.q).cwiseAbs().maxCoeff(), kSameSolutionTol);
}

// The motor spring's natural twist tau_bar = tau_bar(0) + motor_twist_offset belongs to the
// accepted state: the network's tau_bar(0) is never written, and a rejected trial leaves the
// motor's record (last command and speed) as it was.
TEST(SolverFailure, FailedStepLeavesTheMotorAndTheNetworkAsTheyWere) {
  const SimulationConfig c = design1();
  ImplicitStepper stepper = makeStepper(c);
  Motor motor(std::make_shared<ConstantMotor>(c.motor.omega));
  RodState state = stepper.initialState();
  const double tau_bar0 = motorTauBar(stepper);
  for (int k = 0; k < kWarmupSteps; ++k) stepper.step(state, c.dt, motor);
  EXPECT_EQ(motorTauBar(stepper), tau_bar0) << "a step wrote the network's natural twist";
  // docs/model.md 1.9: tau_bar(t) = tau_bar(0) + sum omega dt
  EXPECT_NEAR(state.motor_twist_offset, kWarmupSteps * c.dt * c.motor.omega, kTimeTol);
  const Motor::Record before = motor.record();
  EXPECT_EQ(before.command, c.motor.omega);
  motor.setSchedule(std::make_shared<ConstantMotor>(2.0 * c.motor.omega));
  stepper.options().max_iterations = 1;
  stepper.options().residual_tolerance = 1e-14;
  EXPECT_THROW(stepper.step(state, c.dt, motor), SolverFailure);
  EXPECT_EQ(motor.lastCommand(), before.command) << "record left at a rejected trial's command";
  EXPECT_EQ(motor.lastSpeed(), before.speed);
  EXPECT_EQ(motorTauBar(stepper), tau_bar0);
}

TEST(SolverFailure, HugeStepThrowsAndLeavesStateUnchanged) {
  Simulation sim(design1(kHugeStep));
  const RodState before = sim.state();
  const std::string msg = solverFailureOf([&] { sim.step(); });
  EXPECT_TRUE(identical(sim.state(), before));
  EXPECT_TRUE(allFinite(sim.state()));
  EXPECT_TRUE(contains(msg, "dt = ")) << msg;
  EXPECT_TRUE(contains(msg, "subdivisions")) << msg;
}

TEST(SolverFailure, InvalidTimeStepIsRejected) {
  const SimulationConfig c = design1();
  ImplicitStepper stepper = makeStepper(c);
  const ConstantMotor motor(c.motor.omega);
  RodState state = stepper.initialState();
  const RodState before = state;
  for (double dt : {0.0, -0.01, kNaN, kInf}) {
    SCOPED_TRACE(dt);
    const std::string msg = solverFailureOf([&] { stepper.step(state, dt, motor); });
    EXPECT_TRUE(contains(msg, "time step")) << msg;
    EXPECT_TRUE(identical(state, before));
  }
}

TEST(SolverFailure, SimulationRunStopsAtTheFailureWithFiniteSamples) {
  Simulation sim(design1(kImpossibleSolver));
  EXPECT_THROW(sim.run(1.0), SolverFailure);
  EXPECT_EQ(sim.time(), 0.0);
  for (const TrajectorySample& s : sim.trajectory()) {
    EXPECT_TRUE(s.head_position.allFinite());
    EXPECT_TRUE(std::isfinite(s.omega_h));
  }
}

// ---------------------------------------------------------------------------------------------
// (b) Subdivision that recovers
// ---------------------------------------------------------------------------------------------

TEST(Subdivision, StepThatFailsWholeCompletesInHalves) {
  // Without subdivision the step is not solvable...
  std::vector<std::string> no_subdivision = kNeedsSubdivision;
  no_subdivision.push_back("solver.max_subdivision_depth=0");
  Simulation strict(design1(no_subdivision));
  const std::string msg = solverFailureOf([&] { strict.step(); });
  EXPECT_TRUE(contains(msg, "after 0 subdivisions")) << msg;

  // ... with it the step completes.
  Simulation sim(design1(kNeedsSubdivision));
  StepReport report;
  ASSERT_NO_THROW(report = sim.step());
  EXPECT_GT(report.substeps, 1);
  EXPECT_GT(report.newton_iterations, 0);
  EXPECT_LT(report.residual, sim.config().solver.residual_tolerance);
  EXPECT_NEAR(sim.time(), kBigDt, kTimeTol);
  EXPECT_TRUE(allFinite(sim.state()));
  EXPECT_EQ(sim.sample().subdivided_steps, 1);
  // The motor has turned by omega dt in total.
  EXPECT_NEAR(sim.state().motor_twist_offset, units::rpmToRadPerSec(1000.0) * kBigDt, 1e-9);
  // The head moved, spins finitely.
  EXPECT_GT(std::abs(sim.sample().omega_h), 0.0);
  EXPECT_TRUE(std::isfinite(sim.sample().omega_h));
}

TEST(Subdivision, MatchesExplicitHalfSteps) {
  const SimulationConfig c = design1(kNeedsSubdivision);
  const ConstantMotor motor(c.motor.omega);
  ImplicitStepper subdivided = makeStepper(c);
  RodState state = subdivided.initialState();
  const StepReport report = subdivided.step(state, kBigDt, motor);
  ASSERT_GT(report.substeps, 1);

  // Reproduce the same sub-step sequence by hand: halves, each subdivided as needed.
  ImplicitStepper manual = makeStepper(c);
  RodState manual_state = manual.initialState();
  int manual_substeps = 0;
  for (int half = 0; half < 2; ++half)
    manual_substeps += manual.step(manual_state, 0.5 * kBigDt, motor).substeps;
  EXPECT_EQ(manual_substeps, report.substeps);
  EXPECT_NEAR(manual_state.time, state.time, kTimeTol);
  EXPECT_LT((manual_state.q - state.q).cwiseAbs().maxCoeff(), kSameSolutionTol);
  EXPECT_NEAR(manual_state.motor_twist_offset, state.motor_twist_offset, kTimeTol);
}

TEST(Subdivision, TooFewIterationsRecoverByHalving) {
  // A low iteration cap: at 5000 rpm and dt = 0.05 the whole step needs more Newton iterations
  // than allowed, the halves need fewer.
  Simulation sim(design1({"simulation.dt=0.05", "simulation.output_interval=0.05",
                          "motor.omega_rpm=5000", "motor.ramp_time=0", "solver.max_iterations=8"}));
  StepReport report;
  ASSERT_NO_THROW(report = sim.step());
  EXPECT_GT(report.substeps, 1);
  EXPECT_TRUE(allFinite(sim.state()));
  EXPECT_NEAR(sim.time(), 0.05, kTimeTol);
}

// ---------------------------------------------------------------------------------------------
// (c) Non-finite motor commands
// ---------------------------------------------------------------------------------------------

TEST(MotorCommand, NanAtTheFirstStepIsASolverFailure) {
  Simulation sim(design1());
  sim.setMotor(std::make_shared<CallbackMotor>([](double) { return kNaN; }));
  const RodState before = sim.state();
  const std::string msg = solverFailureOf([&] { sim.step(); });
  EXPECT_TRUE(contains(msg, "motor")) << msg;
  EXPECT_TRUE(contains(msg, "finite")) << msg;
  EXPECT_TRUE(identical(sim.state(), before));
  EXPECT_TRUE(allFinite(sim.state()));
}

TEST(MotorCommand, NonFiniteLaterKeepsTheLastGoodState) {
  constexpr double kGoodOmega = 5.0;  // [rad/s]
  const double switch_time = (kWarmupSteps + 0.5) * design1().dt;
  for (double bad : {kNaN, kInf, -kInf}) {
    SCOPED_TRACE(bad);
    Simulation sim(design1());
    sim.setMotor(std::make_shared<CallbackMotor>(
        [=](double t) { return t < switch_time ? kGoodOmega : bad; }));
    for (int k = 0; k < kWarmupSteps; ++k) ASSERT_NO_THROW(sim.step());
    const RodState before = sim.state();
    const double last_command = sim.lastMotorCommand();
    const std::string msg = solverFailureOf([&] { sim.step(); });
    EXPECT_TRUE(contains(msg, "motor")) << msg;
    EXPECT_TRUE(identical(sim.state(), before));
    EXPECT_TRUE(allFinite(sim.state()));
    EXPECT_EQ(sim.lastMotorCommand(), last_command);
  }
}

TEST(MotorCommand, NanInsideASubdividedStepIsASolverFailure) {
  // The whole step (evaluated at its end) sees a finite speed and fails to converge; the first
  // half then meets the NaN.
  const double end = kBigDt;
  Simulation sim(design1(kNeedsSubdivision));
  const double omega = sim.config().motor.omega;
  sim.setMotor(
      std::make_shared<CallbackMotor>([=](double t) { return t < end - 1e-9 ? kNaN : omega; }));
  const RodState before = sim.state();
  const std::string msg = solverFailureOf([&] { sim.step(); });
  EXPECT_TRUE(contains(msg, "motor")) << msg;
  EXPECT_TRUE(identical(sim.state(), before));
}

// ---------------------------------------------------------------------------------------------
// (d) Reuse of the sparsity pattern and the symbolic analysis
// ---------------------------------------------------------------------------------------------

void expectSingleAnalysis(const std::string& config_name, bool block_lu) {
  SCOPED_TRACE(config_name + (block_lu ? " (block LU)" : " (KLU)"));
  SimulationConfig config = loadSimulationConfig(shippedConfig(config_name));
  config.solver.block_lu = block_lu;
  Simulation sim(config);
  int factorizations = sim.stepper().totalFactorizations();
  int iterations = 0;
  for (int k = 0; k < kManySteps; ++k) {
    iterations += sim.step().newton_iterations;
    if (k == 0 || k == kManySteps - 1) {
      EXPECT_GT(sim.stepper().totalFactorizations(), factorizations) << "step " << k;
      factorizations = sim.stepper().totalFactorizations();
    }
  }
  EXPECT_EQ(sim.stepper().totalAnalyses(), 1);
  // Every step's first update factors a fresh Jacobian; chord updates reuse it
  // (docs/model.md 1.10).
  EXPECT_GE(sim.stepper().totalFactorizations(), kManySteps);
  EXPECT_LE(sim.stepper().totalFactorizations(), iterations);
  const JacobianSolver& solver = sim.stepper().linearSolver();
  if (block_lu) {
    // The robots' block pivots never need KLU's pivoting (and the block LU has no fill).
    EXPECT_EQ(solver.blockFactorizations(), sim.stepper().totalFactorizations());
    EXPECT_EQ(solver.blockFallbacks(), 0);
    EXPECT_EQ(solver.blockLu().fillBlocks(), 0);
  } else {
    const SparseLuSolver& lu = solver.klu();
    EXPECT_EQ(lu.numericFactorizations() + lu.refactorizations(),
              sim.stepper().totalFactorizations());
    EXPECT_GT(lu.refactorizations(), lu.numericFactorizations());  // pivots mostly reused
  }
  EXPECT_TRUE(allFinite(sim.state()));
}

TEST(SymbolicReuse, OneAnalysisOverManyStepsGranular) {
  expectSingleAnalysis(kDesign1, true);
  expectSingleAnalysis(kDesign1, false);
}

TEST(SymbolicReuse, OneAnalysisOverManyStepsInterface) {
  expectSingleAnalysis(kInterfaceRobot, true);
  expectSingleAnalysis(kInterfaceRobot, false);
}

TEST(SymbolicReuse, SubdivisionAndFailureDoNotReanalyse) {
  Simulation sim(design1(kNeedsSubdivision));
  ASSERT_GT(sim.step().substeps, 1);
  EXPECT_EQ(sim.stepper().totalAnalyses(), 1);
  Simulation failing(design1(kImpossibleSolver));
  EXPECT_THROW(failing.step(), SolverFailure);
  EXPECT_THROW(failing.step(), SolverFailure);
  EXPECT_EQ(failing.stepper().totalAnalyses(), 1);
}

}  // namespace
}  // namespace flagella
