// The model-extension effects used by the identification tool, against closed forms that do not
// come from the code under test: a towed head with a granular yield force (Coulomb + Stokes
// velocity), stick-slip jamming (sawtooth period of ds/dt = (F - k_j s)/c), the COM-offset
// gravity couple (docs/model.md 5 balance law), the viscosity drift factor, a DC motor's
// torque-speed curve on the design-1 robot (torque balance on the rigid head, docs/model.md 3.1),
// and the extra weight of a denser flagellum (its volume from the helix's closed-form arc length;
// Stokes linearity of the sinking robot, docs/model.md 5.1).
// Every effect with its default parameters leaves a run unchanged.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/effects/constant_load.h"
#include "flagella_sim/effects/granular_jamming.h"
#include "flagella_sim/effects/granular_yield.h"
#include "flagella_sim/effects/stokes_head_drag.h"
#include "flagella_sim/effects/tail_weight.h"
#include "flagella_sim/effects/viscosity_drift.h"
#include "flagella_sim/rod/network_builder.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "support/temp_dir.h"
#include "support/test_robots.h"

namespace flagella {
namespace {

// ---- a lone rigid head x_0 - x_1 - x_2 towed on x_1 (as in test_actuation_balance) ----------

constexpr double kHeadRadius = 0.02;  // a [m]
constexpr double kViscosity = 1.0;    // mu0 [Pa s]
constexpr double kCt = 1.0;           // C_t
// Translational Stokes drag coefficient c = C_t 6 pi mu a of the head (docs/model.md 3.1).
constexpr double kDrag = kCt * 6.0 * M_PI * kViscosity * kHeadRadius;

/// `density` sets the lumped masses only: mass/drag is ~3 ms at the VPS density.
RodNetwork loneHead(double density) {
  RodMaterial material = testing::vpsMaterial();
  material.density = density;
  return testing::makeLoneHead(kHeadRadius, material);
}

/// Stepper for the lone head with Stokes head drag, a tow force F on x_1 and `extra` effects.
ImplicitStepper towedHead(const Vec3& tow, std::vector<EffectPtr> extra, double force_scale,
                          double density = testing::vpsMaterial().density) {
  const RodNetwork net = loneHead(density);
  std::vector<EffectPtr> effects;
  effects.push_back(std::make_unique<StokesHeadDrag>(kCt, 1.0, kHeadRadius));
  auto load = std::make_unique<ConstantLoad>();
  load->addNodeForce(net.parts.head_center_node, tow);
  effects.push_back(std::move(load));
  for (EffectPtr& e : extra) effects.push_back(std::move(e));
  Medium medium;
  medium.parameters().set("viscosity", kViscosity);
  NewtonOptions options;
  options.force_scale = force_scale;
  options.moment_scale = force_scale * kHeadRadius;
  options.length_scale = kHeadRadius;
  options.residual_tolerance = 1e-8;
  return ImplicitStepper(net, std::move(effects), medium, options);
}

Vec3 headVelocity(const ImplicitStepper& stepper, const RodState& s) {
  return s.qdot.segment<3>(3 * stepper.network().parts.head_center_node);
}

// ---- granular_yield ----------------------------------------------------------------------------

TEST(GranularYield, TowedHeadHoldsBelowTheYieldForceAndMovesAtTheStokesSpeedAbove) {
  constexpr double kYield = 1e-3;          // F_y [N]
  constexpr double kVelocityScale = 1e-6;  // v_s [m/s] (default)
  const Vec3 direction = Vec3(1.0, -2.0, 0.5).normalized();
  const ConstantMotor no_motor(0.0);
  for (double tow : {0.5e-3, 3e-3}) {
    auto yield = std::make_unique<GranularYield>();
    yield->parameters().set("yield_force", kYield);
    yield->parameters().set("velocity_scale", kVelocityScale);
    std::vector<EffectPtr> extra;
    extra.push_back(std::move(yield));
    ImplicitStepper stepper = towedHead(tow * direction, std::move(extra), kYield);
    RodState s = stepper.initialState();
    // mass/drag ~ 3e-3 s against dt = 1e-2 s: the transient is gone after a few steps.
    for (int k = 0; k < 100; ++k) stepper.step(s, 1e-2, no_motor);
    const Vec3 v = headVelocity(stepper, s);
    if (tow < kYield) {
      // F_y v/sqrt(v^2 + v_s^2) <= F  =>  |v| <= v_s r/sqrt(1 - r^2), r = F/F_y
      const double r = tow / kYield;
      const double bound = kVelocityScale * r / std::sqrt(1.0 - r * r);
      std::printf("[yield] F = %.1e N < F_y: |v| = %.3e m/s, bound %.3e m/s\n", tow, v.norm(),
                  bound);
      EXPECT_LT(v.norm(), bound);
    } else {
      // Coulomb + Stokes: v = (F - F_y)/(C_t 6 pi mu a) along F
      const Vec3 expected = (tow - kYield) / kDrag * direction;
      std::printf("[yield] F = %.1e N > F_y: v = %.6e m/s, (F - F_y)/c = %.6e m/s\n", tow, v.norm(),
                  expected.norm());
      EXPECT_LT((v - expected).norm(), 0.01 * expected.norm());
    }
  }
}

// ---- granular_jamming --------------------------------------------------------------------------

TEST(GranularJamming, HeadTowedAlongItsAxisSticksAndSlipsWithTheSawtoothPeriod) {
  constexpr double kStiffness = 1.0;  // k_j [N/m]
  constexpr double kRelease = 1e-3;   // F_r [N]
  constexpr double kTow = 1.05e-3;    // F > F_r [N]
  constexpr double dt = 2e-3;
  constexpr double kDuration = 5.0;
  // A light head (mass/drag ~ 3 us instead of 3 ms) moves quasi-statically: between releases
  // c ds/dt = F - k_j s from s = 0 to k_j s = F_r, so the head covers F_r/k_j per cycle in
  // T = (c/k_j) ln(F/(F - F_r)), at speeds from F/c down to (F - F_r)/c.
  constexpr double kLightDensity = 1.0;  // [kg/m^3]
  const double period = kDrag / kStiffness * std::log(kTow / (kTow - kRelease));
  const double cycle_distance = kRelease / kStiffness;
  auto jamming = std::make_unique<GranularJamming>();
  jamming->parameters().set("stiffness", kStiffness);
  jamming->parameters().set("release_force", kRelease);
  const GranularJamming* effect = jamming.get();
  std::vector<EffectPtr> extra;
  extra.push_back(std::move(jamming));
  ImplicitStepper stepper =
      towedHead(Vec3(0.0, 0.0, kTow), std::move(extra), kRelease, kLightDensity);  // along the axis
  const int x1 = stepper.network().parts.head_center_node;
  RodState s = stepper.initialState();
  const ConstantMotor no_motor(0.0);

  double pushed = 0.0;  // s, restated from the release rule
  std::vector<double> release_times, release_positions, peaks;
  double peak = 0.0, v_min = 1e9, v_max = 0.0;
  const long steps = std::lround(kDuration / dt);
  for (long k = 0; k < steps; ++k) {
    const Vec3 before = nodePosition(s.q, x1);
    const double resistance_before = effect->resistance();
    stepper.step(s, dt, no_motor);
    const Vec3 after = nodePosition(s.q, x1);
    pushed += (after - before).norm();
    if (kStiffness * pushed >= kRelease) {  // the grains release at s_r; the rest carries over
      pushed = std::fmod(pushed, cycle_distance);
      release_times.push_back(s.time);
      release_positions.push_back(after.z());
      peaks.push_back(resistance_before);
    }
    ASSERT_NEAR(effect->resistance(), kStiffness * pushed, 1e-12 * kRelease) << "t = " << s.time;
    peak = std::max(peak, effect->resistance());
    if (!release_times.empty()) {  // speeds over whole cycles after the first release
      v_min = std::min(v_min, headVelocity(stepper, s).norm());
      v_max = std::max(v_max, headVelocity(stepper, s).norm());
    }
  }
  ASSERT_GE(release_times.size(), 4u);
  const size_t n = release_times.size();
  const double measured_period = (release_times[n - 1] - release_times[1]) / (n - 2);
  const double measured_distance = (release_positions[n - 1] - release_positions[1]) / (n - 2);
  std::printf(
      "[jamming] %zu releases, period %.4f s (closed form %.4f), distance %.4e m (%.4e), "
      "speed %.3e .. %.3e m/s (closed form %.3e .. %.3e)\n",
      n, measured_period, period, measured_distance, cycle_distance, v_min, v_max,
      (kTow - kRelease) / kDrag, kTow / kDrag);
  // Distance per cycle: F_r/k_j within one step's travel (< 1e-5 m).
  EXPECT_NEAR(measured_distance, cycle_distance, 0.01 * cycle_distance);
  // Period: the lagged resistance (one step) shifts it by O(dt/T) = 0.2 %.
  EXPECT_NEAR(measured_period, period, 0.01 * period);
  // Releases happen when k_j s reaches F_r: the resistance before a release was within one
  // step's increment (k_j v_max dt) below F_r, and never exceeds F_r.
  for (double p : peaks) {
    EXPECT_LT(p, kRelease);
    EXPECT_GT(p, kRelease - kStiffness * kTow / kDrag * dt);
  }
  EXPECT_LT(peak, kRelease);
  // Intermittent speed: fast right after a release, nearly stuck before the next one.
  EXPECT_NEAR(v_max, kTow / kDrag, 0.01 * kTow / kDrag);
  EXPECT_LT(v_min, 0.1 * v_max);
}

TEST(GranularJamming, HeadTowedAcrossItsAxisMeetsNoResistance) {
  // Sideways motion does not push the grains ahead of the head: s stays 0 and the head moves
  // at the Stokes speed F/c however far it goes.
  constexpr double kTow = 1.05e-3;  // [N]
  auto jamming = std::make_unique<GranularJamming>();
  jamming->parameters().set("stiffness", 1.0);
  jamming->parameters().set("release_force", 1e-3);
  const GranularJamming* effect = jamming.get();
  std::vector<EffectPtr> extra;
  extra.push_back(std::move(jamming));
  ImplicitStepper stepper = towedHead(Vec3(kTow, 0.0, 0.0), std::move(extra), kTow, 1.0);
  RodState s = stepper.initialState();
  const ConstantMotor no_motor(0.0);
  for (int k = 0; k < 500; ++k) stepper.step(s, 2e-3, no_motor);
  const Vec3 v = headVelocity(stepper, s);
  std::printf("[jamming] towed across the axis: v = %.6e m/s, F/c = %.6e m/s, s = %.1e m\n",
              v.norm(), kTow / kDrag, effect->pushedDistance());
  EXPECT_LT(effect->pushedDistance(), 1e-9 * 1e-3);
  EXPECT_NEAR(v.x(), kTow / kDrag, 1e-6 * kTow / kDrag);
}

TEST(GranularJamming, AHeadThatMustStopIsSolvedByTheDampedRetryWithoutSubdivision) {
  // A heavy head coasting along its axis into jammed grains whose resistance exceeds the tow:
  // the step must end (nearly) stuck. Plain Newton on the regularised sign function falls into a
  // two-cycle between the saturated branches; the damped retry (line search) must solve the same
  // step, and the result must satisfy the step's equation: a stuck head, |v| << the coasting speed.
  constexpr double kTow = 0.5e-3, kResistance = 2e-3, kCoast = 5e-3;  // [N], [N], [m/s]
  constexpr double dt = 0.05;
  auto run = [&](bool damped, StepReport* report) {
    auto jamming = std::make_unique<GranularJamming>();
    jamming->parameters().set("stiffness", 1.0);
    jamming->parameters().set("release_force", 1.0);  // no release within the test
    jamming->setPushedDistance(kResistance / 1.0);
    std::vector<EffectPtr> extra;
    extra.push_back(std::move(jamming));
    ImplicitStepper stepper = towedHead(Vec3(0.0, 0.0, kTow), std::move(extra), kTow);
    stepper.options().damped_retry = damped;
    stepper.options().max_subdivision_depth = 0;
    RodState s = stepper.initialState();
    for (int i = 0; i < stepper.network().numNodes(); ++i) s.qdot(3 * i + 2) = kCoast;
    try {
      *report = stepper.step(s, dt, ConstantMotor(0.0));
    } catch (const SolverFailure& e) {
      std::printf("[jamming] %s Newton: %s\n", damped ? "damped" : "plain", e.what());
      return -1.0;
    }
    return headVelocity(stepper, s).norm();
  };
  StepReport plain_report, damped_report;
  const double v_plain = run(false, &plain_report);
  const double v_damped = run(true, &damped_report);
  std::printf(
      "[jamming] coasting head stopped by the grains: plain Newton %s, damped retry v = "
      "%.3e m/s after %d iterations (%d damped)\n",
      v_plain < 0.0 ? "failed" : "converged", v_damped, damped_report.newton_iterations,
      damped_report.damped_retries);
  EXPECT_LT(v_plain, 0.0) << "the scenario no longer needs the damped retry";
  ASSERT_GE(v_damped, 0.0);
  EXPECT_EQ(damped_report.damped_retries, 1);
  EXPECT_EQ(damped_report.substeps, 1);
  EXPECT_LT(v_damped, 1e-3 * kCoast);  // stuck: the resistance exceeds the tow
}

// ---- com_offset --------------------------------------------------------------------------------

TEST(ComOffset, ForcesHaveZeroSumAndTheCoupleOfTheOffsetWeight) {
  const RodNetwork net = testing::makeThreeTailRobot(6);
  const RobotParts& parts = net.parts;
  // A rigidly rotated and shifted robot: the head keeps its rest shape.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Vec3(0.3, -1.0, 0.4).normalized()).toRotationMatrix();
  const Vec3 shift(0.1, -0.2, 0.05);
  VecX q = net.restDofs();
  for (int i = 0; i < net.numNodes(); ++i) q.segment<3>(3 * i) = R * net.rest_positions[i] + shift;
  const ReferenceFrames frames = initialFrames(net, q);
  Medium medium;
  medium.gravity = Vec3(0.4, -9.7, 1.2);
  constexpr double kHeadMass = 0.05;  // m_h [kg]
  for (double offset : {4e-3, -7e-3}) {
    ComOffset e(kHeadMass);
    e.parameters().set("offset", offset);
    e.attach(net);
    VecX F = VecX::Zero(net.ndof());
    e.addForce({net, q, frames, q, VecX::Zero(net.ndof()), 0.01, 0.01, medium, medium.viscosity()},
               F, nullptr);
    Vec3 sum = Vec3::Zero(), couple = Vec3::Zero();
    for (int i = 0; i < net.numNodes(); ++i) {
      sum += F.segment<3>(3 * i);
      couple += nodePosition(q, i).cross(F.segment<3>(3 * i));
      if (i != parts.head_front_node && i != parts.joint_node) {
        EXPECT_EQ(F.segment<3>(3 * i).norm(), 0.0) << "node " << i;
      }
    }
    EXPECT_EQ(F.tail(net.numEdges()).norm(), 0.0);
    // docs/model.md 5: the real couple is l ahat x (m_h g), ahat = t^0 (nose toward tails)
    const Vec3 ahat =
        (nodePosition(q, parts.head_center_node) - nodePosition(q, parts.head_front_node))
            .normalized();
    const Vec3 expected = offset * ahat.cross(kHeadMass * medium.gravity);
    std::printf("[com_offset] l = %+.0e m: |sum F| = %.1e N, couple error %.1e of %.3e N m\n",
                offset, sum.norm(), (couple - expected).norm(), expected.norm());
    EXPECT_LT(sum.norm(), 1e-15);
    EXPECT_LT((couple - expected).norm(), 1e-12 * expected.norm());
    // The weight (+M_a g, along gravity) sits on the COM side: x_2 for l > 0, x_0 for l < 0.
    const int com_side = offset > 0.0 ? parts.joint_node : parts.head_front_node;
    EXPECT_GT(F.segment<3>(3 * com_side).dot(medium.gravity), 0.0);
  }
}

TEST(ComOffset, HeadMassDefaultsToTheDisplacedMediumAndIsANamedParameter) {
  const std::string design1 = std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml";
  // docs/model.md 8.1 / config: rho_m = 1000 kg/m^3, a = 0.02 m, L_head = 2 a
  const double expected = 1000.0 * M_PI * 0.02 * 0.02 * 0.04;
  Simulation sim(loadSimulationConfig(design1, {"effects.com_offset.offset=0.002"}));
  EXPECT_NEAR(sim.parameter("effects.com_offset.head_mass"), expected, 1e-12 * expected);
  sim.setParameter("effects.com_offset.head_mass", 0.2);
  EXPECT_EQ(sim.parameter("effects.com_offset.head_mass"), 0.2);
  EXPECT_EQ(sim.parameterSpec("effects.com_offset.offset").unit, "m");
  const SimulationConfig c = loadSimulationConfig(design1, {"effects.com_offset.head_mass=0.3"});
  EXPECT_EQ(Simulation(c).parameter("effects.com_offset.head_mass"), 0.3);
  const std::string msg = testing::errorMessageOf<ConfigError>(
      [&] { loadSimulationConfig(design1, {"effects.com_offset.offset=0.5"}); });
  EXPECT_NE(msg.find("effects.com_offset.offset"), std::string::npos) << msg;
}

// ---- tail_weight
// ---------------------------------------------------------------------------------

TEST(TailWeight, TotalForceIsTheExtraDensityTimesTheFlagellumsVolumeTimesG) {
  // config/helical_robot.yaml: R_t 18 mm, lambda 36 mm, 3.5 pitches, r0 3.08 mm, 5 mm edges
  const std::string helical = std::string(FLAGELLA_CONFIG_DIR) + "/helical_robot.yaml";
  Simulation sim(loadSimulationConfig(helical, {}));
  const RodNetwork& net = sim.network();
  constexpr double kHelixRadius = 0.018, kPitch = 0.036, kPitchCount = 3.5, kRadius = 3.08e-3;
  ASSERT_EQ(net.parts.tail_edges.size(), 1u);
  const int hook = net.parts.tail_edges[0].front();
  // the helix's arc length (closed form) plus the hook edge; the edges are chords of the helix,
  // 0.3 % shorter than its arcs at 5 mm
  const double length =
      kPitchCount * std::hypot(2.0 * M_PI * kHelixRadius, kPitch) + net.rest_lengths[hook];
  const double volume = M_PI * kRadius * kRadius * length;
  Medium medium;
  medium.gravity = Vec3(0.3, -9.8, 0.2);
  const VecX q = sim.state().q;
  for (double drho : {25.0, -8.0}) {
    TailWeight e;
    e.parameters().set("extra_density", drho);
    e.attach(net);
    VecX F = VecX::Zero(net.ndof());
    e.addForce({net, q, sim.state().frames, q, VecX::Zero(net.ndof()), 0.01, 0.0, medium,
                medium.viscosity()},
               F, nullptr);
    Vec3 sum = Vec3::Zero();
    for (int i = 0; i < net.numNodes(); ++i) sum += F.segment<3>(3 * i);
    for (const int i : net.parts.head_nodes)
      if (i != net.parts.tail_nodes[0].front()) {
        EXPECT_EQ(F.segment<3>(3 * i).norm(), 0.0) << "head node " << i;
      }
    EXPECT_EQ(F.tail(net.numEdges()).norm(), 0.0);  // no moments on the twist DOFs
    const Vec3 expected = drho * volume * medium.gravity;
    std::printf("[tail_weight] drho = %+.0f kg/m^3: |sum F| = %.4e N, closed form %.4e N\n", drho,
                sum.norm(), expected.norm());
    EXPECT_LT((sum - expected).norm(), 0.01 * expected.norm());
    EXPECT_GT(sum.dot(drho * medium.gravity), 0.0);  // denser: along gravity; lighter: against
  }
}

TEST(TailWeight, SinkingIsLinearInTheExtraDensityAndNoneWithoutIt) {
  // The coarse helical robot, motor off, neutrally buoyant as configured: only the extra weight
  // moves it, and in Stokes flow the motion is linear in it (small displacements over 2 s), so
  // +drho and -drho move the head by opposite vectors and drho = 0 leaves it at rest. A tight
  // Newton tolerance: from rest, the weight of 1 kg/m^3 (1.3e-4 N) is below the config's.
  const std::string coarse =
      std::string(FLAGELLA_CONFIG_DIR) + "/identification/helical_shore32_coarse.yaml";
  const auto headShift = [&](double drho) {
    Simulation sim(loadSimulationConfig(
        coarse, {"motor.omega_rpm=0", "solver.residual_tolerance=1e-9",
                 "effects.tail_weight.extra_density=" + std::to_string(drho)}));
    const int head = sim.network().parts.head_center_node;
    const Vec3 start = sim.state().q.segment<3>(3 * head);
    for (int k = 0; k < 200; ++k) sim.step();
    return Vec3(sim.state().q.segment<3>(3 * head) - start);
  };
  const Vec3 down = headShift(1.0), up = headShift(-1.0), none = headShift(0.0);
  const Vec3 gravity = loadSimulationConfig(coarse, {}).medium.gravity;
  std::printf(
      "[tail_weight] head shift in 2 s: +1 kg/m^3 (%.3e %.3e %.3e) m, -1 (%.3e %.3e %.3e) "
      "m, 0: %.1e m\n",
      down.x(), down.y(), down.z(), up.x(), up.y(), up.z(), none.norm());
  EXPECT_GT(down.dot(gravity), 0.0);  // the head sinks with its heavier flagellum
  EXPECT_GT(down.norm(), 1e-5);
  EXPECT_LT((down + up).norm(), 0.02 * down.norm());
  EXPECT_LT(none.norm(), 1e-3 * down.norm());
}

// ---- viscosity_drift ---------------------------------------------------------------------------

double driftFactor(double rate_per_hour, double session_time, double t) {
  return 1.0 + rate_per_hour * (session_time + t) / units::kSecondsPerHour;
}

TEST(ViscosityDrift, HeadDragAtTimeTIsTheNoDriftDragTimesTheFactor) {
  constexpr double kRate = 0.6, kSession = 1800.0;
  const Vec3 tow(2e-3, 1e-3, -1e-3);
  auto drift = std::make_unique<ViscosityDrift>();
  drift->parameters().set("rate", kRate);
  drift->parameters().set("session_time", kSession);
  std::vector<EffectPtr> extra;
  extra.push_back(std::move(drift));
  ImplicitStepper stepper = towedHead(tow, std::move(extra), tow.norm());
  const RodNetwork& net = stepper.network();
  StokesHeadDrag probe(kCt, 1.0, kHeadRadius);
  probe.attach(net);
  Medium no_drift;
  no_drift.parameters().set("viscosity", kViscosity);
  RodState s = stepper.initialState();
  const ConstantMotor no_motor(0.0);
  double worst_force = 0.0, worst_speed = 0.0;
  for (int k = 0; k < 100; ++k) {
    const RodState start = s;
    stepper.step(s, 1e-2, no_motor);
    const double factor = driftFactor(kRate, kSession, s.time);
    // The drag at the viscosity the stepper used for this step against the no-drift drag
    // (viscosity mu0) times the drift law's factor.
    auto dragWith = [&](double viscosity) {
      VecX F = VecX::Zero(net.ndof());
      probe.addForce({net, s.q, s.frames, start.q, start.qdot, 1e-2, s.time, no_drift, viscosity},
                     F, nullptr);
      return F;
    };
    const VecX drifted = dragWith(stepper.currentViscosity());
    const VecX expected = factor * dragWith(kViscosity);
    ASSERT_GT(expected.norm(), 0.0) << "the towed head must feel a drag";
    worst_force = std::max(worst_force, (drifted - expected).norm() / expected.norm());
    // Towed head: v(t) = F/(C_t 6 pi mu(t) a) once the start transient (~3 ms) has decayed.
    if (s.time > 0.1)
      worst_speed =
          std::max(worst_speed,
                   std::abs(headVelocity(stepper, s).norm() * kDrag * factor / tow.norm() - 1.0));
  }
  std::printf("[viscosity_drift] drag vs factor x no-drift drag: %.1e; towed speed: %.1e\n",
              worst_force, worst_speed);
  EXPECT_LT(worst_force, 1e-12);
  EXPECT_LT(worst_speed, 1e-4);
}

TEST(ViscosityDrift, FollowsTheViscosityParameterAndOverrides) {
  const std::string design1 = std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml";
  constexpr double kRate = 0.5, kSession = 7200.0, kMu0 = 6.828;  // docs/model.md 8.1 mu
  Simulation sim(loadSimulationConfig(
      design1, {"robot.tail_edges=10", "simulation.dt=0.02", "effects.viscosity_drift.rate=0.5",
                "effects.viscosity_drift.session_time=7200"}));
  for (int k = 0; k < 3; ++k) sim.step();
  EXPECT_NEAR(sim.currentViscosity(), kMu0 * driftFactor(kRate, kSession, sim.time()),
              1e-12 * kMu0);
  EXPECT_EQ(sim.parameter("medium.viscosity"), kMu0);  // the parameter stays mu0
  sim.setParameter("medium.viscosity", 5.0);           // mu0 is read at every step
  sim.step();
  EXPECT_NEAR(sim.currentViscosity(), 5.0 * driftFactor(kRate, kSession, sim.time()), 1e-12 * 5.0);
}

TEST(ViscosityDrift, FactorDownToTheMinimumIsAnErrorNamingTheRate) {
  // mu/mu0 = 1 - (t_s + t)/3600 reaches 0.05 at t_s + t = 3420 s: t = 0.045 s here.
  auto drift = std::make_unique<ViscosityDrift>();
  drift->parameters().set("rate", -1.0);
  drift->parameters().set("session_time", 3419.955);
  std::vector<EffectPtr> extra;
  extra.push_back(std::move(drift));
  ImplicitStepper stepper = towedHead(Vec3(1e-3, 0.0, 0.0), std::move(extra), 1e-3);
  RodState s = stepper.initialState();
  const ConstantMotor no_motor(0.0);
  for (int k = 0; k < 4; ++k) stepper.step(s, 1e-2, no_motor);
  const RodState before = s;
  const std::string msg =
      testing::errorMessageOf<std::runtime_error>([&] { stepper.step(s, 1e-2, no_motor); });
  std::printf("[viscosity_drift] %s\n", msg.c_str());
  EXPECT_NE(msg.find("effects.viscosity_drift.rate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("t = 0.05 s"), std::string::npos) << msg;
  EXPECT_EQ(s.time, before.time);  // the failed step left the state unchanged
  EXPECT_EQ((s.q - before.q).norm(), 0.0);
}

// ---- dc_motor on the design-1 robot ------------------------------------------------------------

// docs/model.md 8.1 inputs, restated: head torque prefactor, granular mu, head radius, motor speed.
constexpr double kDesign1Cr = 0.039;
constexpr double kDesign1Mu = 6.828;
constexpr double kDesign1A = 0.02;
constexpr double kMotorOmega = units::rpmToRadPerSec(100.0);  // [rad/s]
// Head drag torque per unit head spin, C_r 8 pi mu a^3 (docs/model.md 3.1).
const double kHeadTorquePerSpin = kDesign1Cr * 8.0 * M_PI * kDesign1Mu * std::pow(kDesign1A, 3);

std::vector<std::string> fastDesign1(double duration) {
  return {"robot.tail_edges=10", "simulation.dt=0.02",
          "simulation.duration=" + std::to_string(duration), "simulation.steady_fraction=0.5"};
}

SummaryMetrics runDesign1(std::vector<std::string> overrides, double duration) {
  const std::vector<std::string> base = fastDesign1(duration);
  overrides.insert(overrides.begin(), base.begin(), base.end());
  Simulation sim(
      loadSimulationConfig(std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml", overrides));
  sim.run(duration);
  return sim.summary();
}

TEST(DcMotor, SteadySpinFollowsTheTorqueSpeedCurve) {
  constexpr double kDuration = 20.0;  // steady window 10 .. 20 s
  // Default stall torque: the motor turns at the commanded (no-load) speed.
  const SummaryMetrics free = runDesign1({"effects.dc_motor={}"}, kDuration);
  const double free_sum = free.omega_h + free.omega_t;
  std::printf("[dc_motor] default stall: omega_h + omega_t = %.6f vs omega_cmd %.6f (%.1e)\n",
              free_sum, kMotorOmega, free_sum / kMotorOmega - 1.0);
  EXPECT_NEAR(free_sum, kMotorOmega, 1e-4 * kMotorOmega);
  EXPECT_NEAR(free.omega_motor_mean, kMotorOmega, 1e-4 * kMotorOmega);

  // A stall torque 4x the free-running head load: the load settles near 20 % of stall.
  const double stall = 4.0 * kHeadTorquePerSpin * free.omega_h;
  char stall_text[64];
  std::snprintf(stall_text, sizeof stall_text, "effects.dc_motor.stall_torque=%.17g", stall);
  const SummaryMetrics loaded = runDesign1({stall_text}, kDuration);
  // Torque balance on the rigid head: the motor's load is the head drag torque.
  const double load = kHeadTorquePerSpin * loaded.omega_h;
  const double expected = kMotorOmega * (1.0 - load / stall);
  const double sum = loaded.omega_h + loaded.omega_t;
  std::printf(
      "[dc_motor] stall %.4e N m, load/stall %.4f: omega_h + omega_t = %.6f vs "
      "omega_cmd (1 - tau/tau_stall) = %.6f (%.1e); mean applied speed %.6f\n",
      stall, load / stall, sum, expected, sum / expected - 1.0, loaded.omega_motor_mean);
  EXPECT_GT(load / stall, 0.15);
  EXPECT_LT(load / stall, 0.25);
  EXPECT_NEAR(sum, expected, 0.02 * expected);
  EXPECT_NEAR(loaded.omega_motor_mean, expected, 0.02 * expected);
  EXPECT_NEAR(loaded.omega_T_mean, kMotorOmega, 1e-12);  // omega_T stays the command
}

// ---- configs switch the effects on by name; parameters are named and range-checked --------

TEST(Config, NewEffectsAreSwitchedOnAndTheirParametersNamed) {
  const testing::TempDir dir;
  const std::string path = dir.write("c.yaml",
                                     "robot: {tail_edges: 10}\n"
                                     "motor: {omega_rpm: 60}\n"
                                     "effects:\n"
                                     "  rft: {}\n"
                                     "  stokes_head: {}\n"
                                     "  granular_yield: {yield_force: 1.0e-3}\n"
                                     "  granular_jamming: {stiffness: 2.0, release_force: 5.0e-4}\n"
                                     "  com_offset: {offset: -0.003}\n"
                                     "  viscosity_drift: {rate: 0.1, session_time: 600}\n"
                                     "  dc_motor: {stall_torque: 0.01}\n");
  Simulation sim(loadSimulationConfig(path, {"effects.granular_yield.velocity_scale=1e-5"}));
  EXPECT_EQ(sim.parameter("effects.granular_yield.yield_force"), 1e-3);
  EXPECT_EQ(sim.parameter("effects.granular_yield.velocity_scale"), 1e-5);
  EXPECT_EQ(sim.parameter("effects.granular_jamming.stiffness"), 2.0);
  EXPECT_EQ(sim.parameter("effects.granular_jamming.release_force"), 5e-4);
  EXPECT_EQ(sim.parameter("effects.com_offset.offset"), -0.003);
  EXPECT_EQ(sim.parameter("effects.viscosity_drift.rate"), 0.1);
  EXPECT_EQ(sim.parameter("effects.viscosity_drift.session_time"), 600.0);
  EXPECT_EQ(sim.parameter("effects.dc_motor.stall_torque"), 0.01);
  sim.setParameter("effects.granular_jamming.velocity_scale", 2e-6);
  EXPECT_EQ(sim.parameter("effects.granular_jamming.velocity_scale"), 2e-6);
  for (const char* name : {"effects.granular_yield.yield_force",
                           "effects.granular_jamming.stiffness", "effects.com_offset.head_mass",
                           "effects.viscosity_drift.rate", "effects.dc_motor.stall_torque"}) {
    const ParameterSpec& spec = sim.parameterSpec(name);
    EXPECT_FALSE(spec.unit.empty()) << name;
    EXPECT_FALSE(spec.description.empty()) << name;
  }
  sim.run(0.2);                                             // all five together step
  EXPECT_GT(sim.lastMotorCommand(), sim.lastMotorSpeed());  // dc_motor slows the motor
  const std::string msg = testing::errorMessageOf<ConfigError>(
      [&] { loadSimulationConfig(path, {"effects.granular_yield.yield_force=20"}); });
  EXPECT_NE(msg.find("effects.granular_yield.yield_force must be in [0, 10]"), std::string::npos)
      << msg;
  const std::string set_msg = testing::errorMessageOf<ConfigError>(
      [&] { sim.setParameter("effects.dc_motor.stall_torque", 0.0); });
  EXPECT_NE(set_msg.find("effects.dc_motor.stall_torque"), std::string::npos) << set_msg;
}

// ---- defaults are no-ops ---------------------------------------------------------------------

TEST(DefaultParameters, EveryNewEffectLeavesTheRunUnchanged) {
  constexpr double kDuration = 1.0;
  auto finalState = [&](const std::string& effect) {
    std::vector<std::string> overrides = fastDesign1(kDuration);
    if (!effect.empty()) overrides.push_back("effects." + effect + "={}");
    Simulation sim(loadSimulationConfig(std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml",
                                        overrides));
    sim.run(kDuration);
    return sim.state().q;
  };
  const VecX reference = finalState("");
  const double scale = reference.cwiseAbs().maxCoeff();
  for (const std::string effect :
       {"granular_yield", "granular_jamming", "com_offset", "viscosity_drift", "dc_motor"}) {
    const VecX q = finalState(effect);
    const double diff = (q - reference).cwiseAbs().maxCoeff();
    std::printf("[defaults] %-17s max |q - q_ref| = %.2e (max |q| %.2e)\n", effect.c_str(), diff,
                scale);
    if (effect != "dc_motor") {
      EXPECT_LE(diff, 1e-12 * scale) << effect;
    } else {
      // The default stall torque (1e6 N m, the top of its range) is finite: the motor runs slow
      // by tau_load/tau_stall <= C_r 8 pi mu a^3 omega_cmd / 1e6 ~ 6e-10, so the spin angles
      // lag by at most omega_cmd t times that.
      const double droop = kHeadTorquePerSpin * kMotorOmega / 1e6;
      EXPECT_LE(diff, kMotorOmega * kDuration * droop) << effect;
    }
  }
}

}  // namespace
}  // namespace flagella
