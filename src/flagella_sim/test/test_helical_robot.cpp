// Tests of the uni-flagellar helical robot (docs/model.md 8.4): the built geometry against the
// helix recomputed here from its definition, the rest state, stiffnesses and masses against
// docs/model.md 1.4 and 1.8, the gimbal's fixed DOFs, input validation, the shipped configs, the
// flagellum tilt (8.4.4) and short runs.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/medium.h"
#include "flagella_sim/elastic/bend_twist_energy.h"
#include "flagella_sim/elastic/stretching_energy.h"
#include "flagella_sim/outputs/trajectory.h"
#include "flagella_sim/robots/flagellum_tilt.h"
#include "flagella_sim/robots/helical_robot.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr char kRunExe[] = FLAGELLA_RUN_EXE;

// docs/model.md 8.4.1 values, restated here independently of the HelicalGeometry defaults.
constexpr double kHeadRadius = 0.018;                // R_H [m]
constexpr double kHelixRadius = 0.018;               // R_t [m]
constexpr double kPitch = 0.036;                     // lambda [m]
constexpr double kPitchCount = 3.5;                  // L_t / lambda
constexpr double kHookLength = 0.0188;               // L_h [m]
constexpr double kEdgeLength = 5e-3;                 // Dl [m]
constexpr double kFilamentRadius = 1.584e-3;         // r0 [m]
constexpr double kShippedFilamentRadius = 3.080e-3;  // r0 of helical_robot.yaml [m]
constexpr double kYoungsModulus = 1.225e6;           // E [Pa]
constexpr double kDensity = 1240.0;                  // rho [kg/m^3]
constexpr double kRigidFactor = 1000.0;
constexpr int kHeadAndHookNodes = 5;  // x_0 .. x_4: the helix adds one node per edge

// Positions are built from a few products of the inputs: round-off level for ~0.1 m.
constexpr double kPositionTol = 1e-12;
// Stiffnesses and masses: a few roundings of products.
constexpr double kRelativeTol = 1e-12;
// The rest state is the natural state: the elastic gradient vanishes up to round-off of
// stiffness x strain ~ 1e3 N x 1e-16.
constexpr double kRestGradientTol = 1e-10;
// Tilt of the undeformed helix's centre line (docs/model.md 8.4.4: about 1e-4 deg).
constexpr double kRestTiltTolDeg = 1e-2;
// The brief's requirement for the rest tilt.
constexpr double kRestTiltLimitDeg = 1.0;

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

HelicalGeometry defaultGeometry() {
  HelicalGeometry g;
  g.head_radius = kHeadRadius;
  g.helix_radius = kHelixRadius;
  g.pitch = kPitch;
  g.pitch_count = kPitchCount;
  g.hook_length = kHookLength;
  g.edge_length = kEdgeLength;
  g.flagellum = {kYoungsModulus, 0.5, kFilamentRadius, kDensity};
  g.rigid_factor = kRigidFactor;
  return g;
}

// Independent L_arc and edge count (docs/model.md 8.4.1).
double arcLength(double R, double lambda, double pitches) {
  return pitches * std::sqrt(std::pow(2.0 * M_PI * R, 2) + lambda * lambda);
}
int helixEdgeCount(const HelicalGeometry& g) {
  const double arc = arcLength(g.helix_radius, g.pitch, g.pitch_count);
  return std::max(2, static_cast<int>(std::lround(arc / g.edge_length)));
}

std::vector<Vec3> helixPositions(const RodNetwork& net) {
  std::vector<Vec3> p;
  for (int node : helixNodes(net.parts)) p.push_back(net.rest_positions[node]);
  return p;
}

std::string configErrorOf(const std::function<void()>& fn) {
  return testing::errorMessageOf<ConfigError>(fn);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------------------

TEST(HelicalGeometry, NodeCountAndParts) {
  const HelicalGeometry g = defaultGeometry();
  const RodNetwork net = buildHelicalRobot(g);
  const int n_e = helixEdgeCount(g);
  EXPECT_EQ(n_e, 83);  // 0.4154 m of arc in 5 mm edges
  EXPECT_EQ(net.numNodes(), kHeadAndHookNodes + n_e);
  EXPECT_EQ(net.numEdges(), net.numNodes() - 1);
  const RobotParts& p = net.parts;
  EXPECT_EQ(p.head_front_node, 0);
  EXPECT_EQ(p.head_center_node, 1);
  EXPECT_EQ(p.joint_node, 2);
  EXPECT_EQ(p.head_edge, 0);
  EXPECT_EQ(p.shaft_edge, 1);
  EXPECT_EQ(p.head_nodes, (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(p.tail_nodes.size(), 1u);
  ASSERT_EQ(p.tail_edges.size(), 1u);
  // one chain x_3 .. x_{N-1}, hook e^3 first; consecutive nodes are the segments' ends
  ASSERT_EQ(static_cast<int>(p.tail_nodes[0].size()), net.numNodes() - 3);
  ASSERT_EQ(p.tail_edges[0].size() + 1, p.tail_nodes[0].size());
  EXPECT_EQ(p.tail_nodes[0].front(), 3);
  EXPECT_EQ(p.tail_edges[0].front(), 3);
  for (size_t k = 0; k < p.tail_edges[0].size(); ++k) {
    const EdgeDef& e = net.edges[p.tail_edges[0][k]];
    EXPECT_EQ(e.start_node, p.tail_nodes[0][k]);
    EXPECT_EQ(e.end_node, p.tail_nodes[0][k + 1]);
  }
  EXPECT_EQ(static_cast<int>(helixNodes(p).size()), n_e + 1);
  EXPECT_EQ(helixNodes(p).front(), 4);
}

TEST(HelicalGeometry, HeadPlateAndHook) {
  const RodNetwork net = buildHelicalRobot(defaultGeometry());
  const std::vector<Vec3>& x = net.rest_positions;
  EXPECT_LT((x[0] - Vec3(0, 0, -kHeadRadius)).norm(), kPositionTol);
  EXPECT_LT(x[1].norm(), kPositionTol);
  EXPECT_LT((x[2] - Vec3(0, 0, kHeadRadius)).norm(), kPositionTol);
  const Vec3 plate = x[3] - x[2];
  EXPECT_NEAR(plate.norm(), kHelixRadius, kPositionTol);
  EXPECT_NEAR(plate.z(), 0.0, kPositionTol);  // radial: normal to the axis
  const Vec3 hook = x[4] - x[3];
  EXPECT_NEAR(hook.z(), kHookLength, kPositionTol);
  EXPECT_NEAR(hook.head<2>().norm(), 0.0, kPositionTol);  // axial
  // the helix ends L_t beyond x_4 along the axis
  EXPECT_NEAR(x.back().z() - x[4].z(), kPitchCount * kPitch, kPositionTol);
}

TEST(HelicalGeometry, HelixOnCylinderWithEqualEdges) {
  const HelicalGeometry g = defaultGeometry();
  const RodNetwork net = buildHelicalRobot(g);
  const std::vector<Vec3> h = helixPositions(net);
  for (const Vec3& p : h) EXPECT_NEAR(p.head<2>().norm(), kHelixRadius, kPositionTol);
  double shortest = 1e9, longest = 0.0;
  for (size_t i = 0; i + 1 < h.size(); ++i) {
    const double l = (h[i + 1] - h[i]).norm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  EXPECT_LT(longest / shortest - 1.0, 0.01);
  // chords are a little under the arc per edge, which is within half an edge of Dl over 83 edges
  EXPECT_NEAR(longest, kEdgeLength, 0.01 * kEdgeLength);
  const double arc_per_edge = arcLength(kHelixRadius, kPitch, kPitchCount) / helixEdgeCount(g);
  EXPECT_LE(longest, arc_per_edge);
}

// The pitch measured between consecutive turns: where the unwrapped azimuth passes 2 pi k.
// Azimuth and height are both linear in the node index of an undeformed helix, so linear
// interpolation between nodes is exact.
TEST(HelicalGeometry, PitchFromConsecutiveTurns) {
  for (int chi : {kLeftHanded, kRightHanded}) {
    HelicalGeometry g = defaultGeometry();
    g.handedness = chi;
    const std::vector<Vec3> h = helixPositions(buildHelicalRobot(g));
    std::vector<double> psi{0.0};
    for (size_t i = 1; i < h.size(); ++i) {
      const double a0 = std::atan2(chi * h[i - 1].y(), h[i - 1].x());
      const double a1 = std::atan2(chi * h[i].y(), h[i].x());
      psi.push_back(psi.back() + std::remainder(a1 - a0, 2.0 * M_PI));
    }
    std::vector<double> turn_heights;
    for (size_t i = 0; i + 1 < h.size(); ++i)
      for (int k = 0; k <= static_cast<int>(kPitchCount); ++k) {
        const double target = 2.0 * M_PI * k;
        if (psi[i] <= target && target < psi[i + 1]) {
          const double s = (target - psi[i]) / (psi[i + 1] - psi[i]);
          turn_heights.push_back(h[i].z() + s * (h[i + 1].z() - h[i].z()));
        }
      }
    ASSERT_EQ(turn_heights.size(), 4u);  // phi = 0, 2 pi, 4 pi, 6 pi
    for (size_t k = 1; k < turn_heights.size(); ++k)
      EXPECT_NEAR(turn_heights[k] - turn_heights[k - 1], kPitch, kPositionTol);
  }
}

// (x' x x'').z > 0 means the helix turns counter-clockwise about +z as it rises: right-handed
// for a rising helix; the torsion sign (x' x x'').x''' is the handedness itself.
TEST(HelicalGeometry, HandednessFromDiscreteDerivatives) {
  for (int chi : {kLeftHanded, kRightHanded}) {
    HelicalGeometry g = defaultGeometry();
    g.handedness = chi;
    const std::vector<Vec3> h = helixPositions(buildHelicalRobot(g));
    for (size_t i = 1; i + 2 < h.size(); ++i) {
      const Vec3 d1 = h[i + 1] - h[i - 1];
      const Vec3 d2 = h[i + 1] - 2.0 * h[i] + h[i - 1];
      const Vec3 d3 = h[i + 2] - 3.0 * h[i + 1] + 3.0 * h[i] - h[i - 1];
      EXPECT_EQ(d1.cross(d2).z() > 0.0 ? 1 : -1, chi) << "node " << i;
      EXPECT_EQ(d1.cross(d2).dot(d3) > 0.0 ? 1 : -1, chi) << "node " << i;
    }
  }
}

TEST(HelicalGeometry, AxialLengthAndEdgeCountFollowInputs) {
  HelicalGeometry g = defaultGeometry();
  g.pitch_count = 2.0;
  g.edge_length = 0.01;
  const RodNetwork net = buildHelicalRobot(g);
  const int n_e = static_cast<int>(std::lround(arcLength(kHelixRadius, kPitch, 2.0) / 0.01));
  EXPECT_EQ(net.numNodes(), kHeadAndHookNodes + n_e);
  EXPECT_NEAR(net.rest_positions.back().z(), kHeadRadius + kHookLength + 2.0 * kPitch,
              kPositionTol);
}

// ---------------------------------------------------------------------------------------------
// Rest state, stiffnesses, masses, mounts
// ---------------------------------------------------------------------------------------------

TEST(HelicalRestState, ElasticGradientVanishes) {
  const RodNetwork net = buildHelicalRobot(defaultGeometry());
  const VecX q = net.restDofs();
  const ReferenceFrames frames = initialFrames(net, q);
  VecX gradient = VecX::Zero(net.ndof());
  addStretchingGradientHessian(net, frames, gradient, nullptr);
  addBendTwistGradientHessian(net, q, frames, gradient, nullptr);
  EXPECT_LT(gradient.cwiseAbs().maxCoeff(), kRestGradientTol);
  EXPECT_NEAR(stretchingEnergy(net, q) + bendTwistEnergy(net, q, frames), 0.0, 1e-20);
}

TEST(HelicalRestState, StaysPutWithoutLoads) {
  const RodNetwork net = buildHelicalRobot(defaultGeometry());
  NewtonOptions o;
  o.force_scale = defaultGeometry().flagellum.EI() / std::pow(kPitchCount * kPitch, 2);
  o.moment_scale = defaultGeometry().flagellum.EI() / (kPitchCount * kPitch);
  o.length_scale = kPitchCount * kPitch;
  ImplicitStepper stepper(net, {}, Medium(), o);
  RodState s = stepper.initialState();
  const ConstantMotor off(0.0);
  for (int k = 0; k < 3; ++k) stepper.step(s, 0.01, off);
  EXPECT_LT((s.q - net.restDofs()).cwiseAbs().maxCoeff(), kPositionTol);
}

TEST(HelicalStiffness, RigidPartsAreThousandTimesTheFlagellum) {
  const RodNetwork net = buildHelicalRobot(defaultGeometry());
  // docs/model.md 1.4 for a solid circular section, G = E / 3 at nu = 0.5
  const double EA = kYoungsModulus * M_PI * std::pow(kFilamentRadius, 2);
  const double EI = kYoungsModulus * M_PI * std::pow(kFilamentRadius, 4) / 4.0;
  const double GJ = kYoungsModulus / 3.0 * M_PI * std::pow(kFilamentRadius, 4) / 2.0;
  for (const StretchSpring& s : net.stretch_springs) {
    const double expected = s.edge <= 2 ? kRigidFactor * EA : EA;  // e^0, e^1, plate e^2
    EXPECT_NEAR(s.EA, expected, kRelativeTol * expected) << "edge " << s.edge;
  }
  ASSERT_EQ(static_cast<int>(net.bend_twist_springs.size()), net.numEdges() - 1);
  for (const BendTwistSpring& s : net.bend_twist_springs) {
    EXPECT_EQ(s.edge_f, s.edge_e + 1);                         // one chain of consecutive edges
    const double factor = s.edge_e <= 2 ? kRigidFactor : 1.0;  // T0, T1, T2 at x_1, x_2, x_3
    EXPECT_NEAR(s.EI, factor * EI, kRelativeTol * factor * EI) << "spring at " << s.node_c;
    EXPECT_NEAR(s.GJ, factor * GJ, kRelativeTol * factor * GJ) << "spring at " << s.node_c;
  }
  const BendTwistSpring& motor = net.bend_twist_springs.at(net.parts.motor_spring);
  EXPECT_EQ(motor.edge_e, 0);
  EXPECT_EQ(motor.edge_f, 1);
  EXPECT_EQ(motor.node_c, net.parts.head_center_node);
}

// docs/model.md 8.4.1: hook_stiffness_scale multiplies the hook's joint at x_4 alone.
TEST(HelicalStiffness, HookScaleMultipliesTheHookJointOnly) {
  HelicalGeometry g = defaultGeometry();
  const double EI = kYoungsModulus * M_PI * std::pow(kFilamentRadius, 4) / 4.0;
  const double GJ = kYoungsModulus / 3.0 * M_PI * std::pow(kFilamentRadius, 4) / 2.0;
  constexpr double kScale = 0.37;
  g.hook_stiffness_scale = kScale;
  const RodNetwork net = buildHelicalRobot(g);
  int hook_joints = 0;
  for (const BendTwistSpring& s : net.bend_twist_springs) {
    if (s.edge_e <= 2) continue;                          // the rigid T0, T1, T2
    const bool hook = s.node_c == kHeadAndHookNodes - 1;  // x_4, between e^3 and e^4
    hook_joints += hook;
    const double factor = hook ? kScale : 1.0;
    EXPECT_NEAR(s.EI, factor * EI, kRelativeTol * EI) << "spring at " << s.node_c;
    EXPECT_NEAR(s.GJ, factor * GJ, kRelativeTol * GJ) << "spring at " << s.node_c;
  }
  EXPECT_EQ(hook_joints, 1);
}

// Turn the helix rigidly about x_4, its material frames with it: only the hook's joint strains,
// so the elastic energy is proportional to its stiffness, kScale times the unscaled robot's.
TEST(HelicalStiffness, HookScaleScalesTheEnergyOfABentHook) {
  HelicalGeometry g = defaultGeometry();
  const RodNetwork plain = buildHelicalRobot(g);
  constexpr double kScale = 2.6;
  g.hook_stiffness_scale = kScale;
  const RodNetwork scaled = buildHelicalRobot(g);
  const VecX rest = plain.restDofs();
  const ReferenceFrames rest_frames = initialFrames(plain, rest);
  VecX q = rest;
  const int x4 = kHeadAndHookNodes - 1;
  const Vec3 pivot = q.segment<3>(RodNetwork::positionIndex(x4));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.05, Vec3::UnitY()).toRotationMatrix();
  for (int node = kHeadAndHookNodes; node < plain.numNodes(); ++node) {
    const int i = RodNetwork::positionIndex(node);
    q.segment<3>(i) = pivot + turn * (q.segment<3>(i) - pivot);
  }
  // space-parallel transport gives the turned edges other reference directors than the turned
  // ones; the twist angles make their material frames the turned rest frames (docs/model.md 1.6)
  const ReferenceFrames frames = initialFrames(plain, q);
  for (int edge = kHeadAndHookNodes - 1; edge < plain.numEdges(); ++edge) {
    const Vec3 m1 = turn * (std::cos(rest(plain.thetaIndex(edge))) * rest_frames.d1[edge] +
                            std::sin(rest(plain.thetaIndex(edge))) * rest_frames.d2[edge]);
    q(plain.thetaIndex(edge)) = std::atan2(m1.dot(frames.d2[edge]), m1.dot(frames.d1[edge]));
  }
  const auto elastic = [&](const RodNetwork& net) {
    return stretchingEnergy(net, q) + bendTwistEnergy(net, q, frames);
  };
  const double e_plain = elastic(plain);
  EXPECT_GT(e_plain, 0.0);
  EXPECT_NEAR(elastic(scaled) / e_plain, kScale, 1e-6);
}

TEST(HelicalMasses, HeadNodesCarryTenFlagellumNodes) {
  const HelicalGeometry g = defaultGeometry();
  const RodNetwork net = buildHelicalRobot(g);
  const std::vector<Vec3> h = helixPositions(net);
  const double chord = (h[1] - h[0]).norm();
  const double m_x = kDensity * M_PI * kFilamentRadius * kFilamentRadius * chord;
  for (int node : {0, 1})
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(net.lumped_mass(3 * node + a), 10.0 * m_x, kRelativeTol * m_x);
  const int tip = net.numNodes() - 1;
  EXPECT_NEAR(net.lumped_mass(3 * tip), 0.5 * m_x, kRelativeTol * m_x);
  EXPECT_NEAR(net.lumped_mass(3 * (tip - 1)), m_x, kRelativeTol * m_x);
}

TEST(HelicalMount, GimbalFixesPivotAndHeadRollOnly) {
  HelicalGeometry g = defaultGeometry();
  const RodNetwork free = buildHelicalRobot(g);
  EXPECT_EQ(std::count(free.fixed_dof.begin(), free.fixed_dof.end(), true), 0);
  g.mount = HelicalMount::kGimbal;
  const RodNetwork net = buildHelicalRobot(g);
  EXPECT_EQ(std::count(net.fixed_dof.begin(), net.fixed_dof.end(), true), 4);
  for (int a = 0; a < 3; ++a) EXPECT_TRUE(net.fixed_dof[RodNetwork::positionIndex(0) + a]);
  EXPECT_TRUE(net.fixed_dof[net.thetaIndex(net.parts.head_edge)]);
}

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

struct BadGeometry {
  const char* what;
  std::function<void(HelicalGeometry&)> edit;
  const char* field;
  const char* reason;  // further text the message must hold ("" for none)
};

TEST(HelicalValidation, EachBadInputNamesItsField) {
  const std::vector<BadGeometry> cases = {
      {"zero pitch", [](HelicalGeometry& g) { g.pitch = 0.0; }, "robot.pitch", "> 0"},
      {"negative helix radius", [](HelicalGeometry& g) { g.helix_radius = -0.01; },
       "robot.helix_radius", "> 0"},
      {"zero filament radius", [](HelicalGeometry& g) { g.flagellum.radius = 0.0; },
       "robot.filament_radius", "> 0"},
      {"turns touch", [](HelicalGeometry& g) { g.pitch = 2.0 * kFilamentRadius; }, "robot.pitch",
       "turns of the helix would touch"},
      {"filament crosses the axis", [](HelicalGeometry& g) { g.helix_radius = kFilamentRadius; },
       "robot.helix_radius", "cross the helix axis"},
      {"zero hook", [](HelicalGeometry& g) { g.hook_length = 0.0; }, "robot.hook_length", "(0, "},
      {"hook too long", [](HelicalGeometry& g) { g.hook_length = 0.13; }, "robot.hook_length",
       "hook longer than the helix's axial length"},
      {"too few pitches", [](HelicalGeometry& g) { g.pitch_count = 0.4; }, "robot.pitch_count",
       "[0.5, 50]"},
      {"too many pitches", [](HelicalGeometry& g) { g.pitch_count = 51.0; }, "robot.pitch_count",
       "[0.5, 50]"},
      {"too few helix edges", [](HelicalGeometry& g) { g.edge_length = 0.2; }, "robot.edge_length",
       "fewer than 4 helix edges"},
      {"bad handedness", [](HelicalGeometry& g) { g.handedness = 0; }, "robot.handedness", ""},
      {"zero head radius", [](HelicalGeometry& g) { g.head_radius = 0.0; }, "robot.head_radius",
       ""},
      {"zero hook stiffness", [](HelicalGeometry& g) { g.hook_stiffness_scale = 0.0; },
       "robot.hook_stiffness_scale", "> 0"},
  };
  for (const BadGeometry& c : cases) {
    SCOPED_TRACE(c.what);
    HelicalGeometry g = defaultGeometry();
    c.edit(g);
    const std::string message = configErrorOf([&] { buildHelicalRobot(g); });
    EXPECT_TRUE(contains(message, c.field)) << message;
    EXPECT_TRUE(contains(message, c.reason)) << message;
  }
}

TEST(HelicalValidation, FourHelixEdgesAreEnough) {
  HelicalGeometry g = defaultGeometry();
  g.edge_length = arcLength(kHelixRadius, kPitch, kPitchCount) / 4.0;
  EXPECT_EQ(buildHelicalRobot(g).numNodes(), kHeadAndHookNodes + 4);
}

std::string helicalConfig(const std::string& robot_extra,
                          const std::string& simulation_extra = "") {
  return "robot:\n  type: helical\n" + robot_extra +
         "medium:\n  viscosity: 1.03\n  gravity: [0, 0, 0]\n"
         "effects:\n  stokes_head:\n    C_t: 1.8\n    C_r: 1.37\n"
         "motor:\n  omega_rpm: 30\n"
         "simulation:\n  dt: 0.01\n  duration: 0.1\n" +
         simulation_extra;
}

TEST(HelicalValidation, ConfigErrorsNameTheField) {
  const TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {helicalConfig("  pitch: -1\n"), "robot.pitch must be in ["},
      {helicalConfig("  pitch_count: 3\n  axial_length: 0.1\n"), "are exclusive"},
      {helicalConfig("  axial_length: 5\n"), "robot.axial_length"},
      {helicalConfig("  handedness: up\n"), "robot.handedness must be one of: left, right"},
      {helicalConfig("  mount: wall\n"), "robot.mount must be one of: untethered, gimbal"},
      {helicalConfig("  n_tails: 2\n"), "unknown field 'robot.n_tails'"},
      {helicalConfig("  pitch: 0.003\n"), "turns of the helix would touch"},
      {helicalConfig("  hook_length: 0.2\n"), "robot.hook_length"},
      {helicalConfig("  hook_stiffness_scale: 200\n"),
       "robot.hook_stiffness_scale must be in [0.01, 100]"},
      {helicalConfig("", "  buckling_tilt_deg: 0\n"), "simulation.buckling_tilt_deg"},
      {helicalConfig("", "  buckling_tilt_deg: 90\n"), "simulation.buckling_tilt_deg"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].first);
    const std::string path = dir.write("bad" + std::to_string(i) + ".yaml", cases[i].first);
    const std::string message = configErrorOf([&] { loadSimulationConfig(path); });
    EXPECT_TRUE(contains(message, cases[i].second)) << message;
    EXPECT_TRUE(contains(message, path)) << message;
  }
}

TEST(HelicalConfig, AxialLengthGivesThePitchCount) {
  const TempDir dir;
  const SimulationConfig c =
      loadSimulationConfig(dir.write("ok.yaml", helicalConfig("  axial_length: 0.144\n")));
  EXPECT_NEAR(c.robotGeometry<HelicalGeometry>().pitch_count, 4.0, 1e-12);
  EXPECT_NEAR(c.robotGeometry<HelicalGeometry>().axialLength(), 0.144, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Shipped configs
// ---------------------------------------------------------------------------------------------

TEST(HelicalConfig, ShippedRobotConfigParses) {
  // the source's Shore 32 robot with the filament radius calibrated on its Shore 22 twin
  constexpr double kFilamentRadius = kShippedFilamentRadius;
  const SimulationConfig c = loadSimulationConfig(shippedConfig("helical_robot.yaml"));
  ASSERT_EQ(c.robotType(), "helical");
  const HelicalGeometry& g = c.robotGeometry<HelicalGeometry>();
  EXPECT_DOUBLE_EQ(g.helix_radius, kHelixRadius);
  EXPECT_DOUBLE_EQ(g.pitch, kPitch);
  EXPECT_DOUBLE_EQ(g.pitch_count, kPitchCount);
  EXPECT_DOUBLE_EQ(g.flagellum.radius, kFilamentRadius);
  EXPECT_DOUBLE_EQ(g.flagellum.youngs_modulus, kYoungsModulus);
  EXPECT_EQ(g.handedness, kLeftHanded);
  EXPECT_EQ(g.mount, HelicalMount::kUntethered);
  // Gravity acts only through com_offset (no gravity effect: neutrally buoyant, docs/model.md 5).
  EXPECT_NEAR(c.medium.gravity.dot(c.medium.up), -9.81, 1e-12);
  for (const EffectSpec& e : c.effects) EXPECT_NE(e.name, "gravity");
  // head drag radius R_H and the sphere's volume pi a^2 L_head = 4/3 pi R_H^3
  const RobotDimensions d = c.robotDimensions();
  EXPECT_DOUBLE_EQ(d.head_radius, kHeadRadius);
  EXPECT_NEAR(M_PI * d.head_radius * d.head_radius * d.head_length,
              4.0 / 3.0 * M_PI * std::pow(kHeadRadius, 3), 1e-18);
  EXPECT_DOUBLE_EQ(d.filament_radius, kFilamentRadius);
  EXPECT_DOUBLE_EQ(d.body_density, kDensity);
  // convergence scales from the flagellum: EI / L_t^2, EI / L_t
  const double EI = kYoungsModulus * M_PI * std::pow(kFilamentRadius, 4) / 4.0;
  EXPECT_NEAR(c.solver.force_scale, EI / std::pow(kPitchCount * kPitch, 2), 1e-12 * EI);
  EXPECT_NEAR(c.solver.length_scale, kPitchCount * kPitch, 1e-15);
  const Simulation sim(c);
  EXPECT_DOUBLE_EQ(sim.parameter("effects.stokes_head.C_t"), 1.512);  // calibrated, model.md 8.4.1
  EXPECT_DOUBLE_EQ(sim.parameter("effects.stokes_head.head_radius"), kHeadRadius);
}

TEST(HelicalConfig, ShippedGimbalConfigParses) {
  const SimulationConfig c = loadSimulationConfig(shippedConfig("helical_gimbal.yaml"));
  ASSERT_EQ(c.robotType(), "helical");
  EXPECT_EQ(c.robotGeometry<HelicalGeometry>().mount, HelicalMount::kGimbal);
  const Simulation sim(c);
  const std::vector<bool>& fixed = sim.network().fixed_dof;
  EXPECT_EQ(std::count(fixed.begin(), fixed.end(), true), 4);
  // no head drag on the gimbal housing (docs/model.md 8.4.2)
  for (const EffectSpec& e : c.effects)
    if (e.name == "stokes_head") {
      EXPECT_EQ(sim.parameter("effects.stokes_head.C_t"), 0.0);
      EXPECT_EQ(sim.parameter("effects.stokes_head.C_r"), 0.0);
    }
}

TEST(HelicalConfig, MultiTailStaysTheDefault) {
  const SimulationConfig c = loadSimulationConfig(shippedConfig("granular_design1.yaml"));
  EXPECT_EQ(c.findRobotGeometry<HelicalGeometry>(), nullptr);
  EXPECT_EQ(c.robotType(), "multi_tail");
}

// ---------------------------------------------------------------------------------------------
// Flagellum tilt (docs/model.md 8.4.4)
// ---------------------------------------------------------------------------------------------

double tiltDeg(const RodNetwork& net, const VecX& q, const HelicalGeometry& g, const Vec3& axis) {
  return units::radToDeg(flagellumTilt(q, helixNodes(net.parts), g.edgesPerTurn(), axis));
}

TEST(FlagellumTilt, UndeformedHelixHasNoTilt) {
  for (double pitches : {1.5, 2.0, 3.0, 3.5, 4.0, 5.0}) {
    SCOPED_TRACE(pitches);
    HelicalGeometry g = defaultGeometry();
    g.pitch_count = pitches;
    const RodNetwork net = buildHelicalRobot(g);
    const double tilt = tiltDeg(net, net.restDofs(), g, Vec3::UnitZ());
    EXPECT_LT(tilt, kRestTiltTolDeg);
    EXPECT_LT(tilt, kRestTiltLimitDeg);
  }
}

// Why the centre line: the nodes' own principal axis is biased at rest (docs/model.md 8.4.4).
TEST(FlagellumTilt, NodesOwnPrincipalAxisIsBiasedAtRest) {
  const HelicalGeometry g = defaultGeometry();
  const RodNetwork net = buildHelicalRobot(g);
  const Vec3 axis = principalAxis(helixPositions(net), Vec3::UnitZ());
  const double tilt = units::radToDeg(std::acos(axis.z()));
  EXPECT_GT(tilt, 0.5);  // about 1.1 deg for 3.5 pitches and 83 edges
  EXPECT_LT(tilt, 2.0);
}

// A helix turned rigidly by alpha about a transverse axis has tilt alpha against the old axis.
TEST(FlagellumTilt, RotatedHelixShowsTheRotationAngle) {
  const HelicalGeometry g = defaultGeometry();
  const RodNetwork net = buildHelicalRobot(g);
  for (double alpha_deg : {5.0, 20.0, 60.0}) {
    const Eigen::AngleAxisd turn(units::degToRad(alpha_deg), Vec3(1, 2, 0).normalized());
    VecX q = net.restDofs();
    for (int node : helixNodes(net.parts))
      q.segment<3>(3 * node) = Vec3(0.01, -0.02, 0.03) + turn * net.rest_positions[node];
    EXPECT_NEAR(tiltDeg(net, q, g, Vec3::UnitZ()), alpha_deg, kRestTiltTolDeg);
    // the reference's sign does not matter: the axis is taken along it
    EXPECT_NEAR(tiltDeg(net, q, g, -Vec3::UnitZ()), alpha_deg, kRestTiltTolDeg);
  }
}

TEST(FlagellumTilt, CentreLineOfUndeformedHelixIsOnTheAxis) {
  const HelicalGeometry g = defaultGeometry();
  const std::vector<Vec3> centre =
      helixCentreLine(helixPositions(buildHelicalRobot(g)), g.edgesPerTurn());
  ASSERT_GE(centre.size(), 50u);
  for (const Vec3& c : centre) EXPECT_LT(c.head<2>().norm(), 1e-3 * kHelixRadius);
}

// ---------------------------------------------------------------------------------------------
// Summary metrics
// ---------------------------------------------------------------------------------------------

TEST(HelicalSummary, HeadingChangeTiltMaxAndBuckled) {
  std::vector<TrajectorySample> samples(11);
  for (int i = 0; i <= 10; ++i) {
    TrajectorySample& s = samples[i];
    s.time = i;
    const double turn = units::degToRad(3.0 * i);  // the head axis turns to 30 deg
    s.head_axis = Vec3(std::sin(turn), 0.0, std::cos(turn));
    s.flagellum_tilt = units::degToRad(i == 2 ? 40.0 : (i == 8 ? 12.0 : 1.0));
  }
  SummaryInputs in;
  in.steady_fraction = 0.5;  // samples 5..10: the 40 deg at t = 2 is outside
  in.buckling_tilt = units::degToRad(15.0);
  SummaryMetrics m = summarize(samples, in);
  EXPECT_NEAR(units::radToDeg(m.heading_change), 30.0, 1e-9);
  EXPECT_NEAR(units::radToDeg(m.flagellum_tilt_max), 12.0, 1e-9);
  EXPECT_NEAR(units::radToDeg(m.flagellum_tilt_mean), (5.0 * 1.0 + 12.0) / 6.0, 1e-9);
  EXPECT_FALSE(m.buckled);
  in.buckling_tilt = units::degToRad(10.0);
  m = summarize(samples, in);
  EXPECT_TRUE(m.buckled);
}

// ---------------------------------------------------------------------------------------------
// Short runs
// ---------------------------------------------------------------------------------------------

constexpr double kShortRun = 0.2;  // [s]

TEST(HelicalRun, ShortUntetheredRunStaysFinite) {
  const SimulationConfig c =
      loadSimulationConfig(shippedConfig("helical_robot.yaml"), {"motor.omega_rpm=30"});
  Simulation sim(c);
  sim.run(kShortRun);
  EXPECT_NEAR(sim.time(), kShortRun, 1e-9);
  EXPECT_TRUE(sim.state().q.allFinite());
  EXPECT_TRUE(sim.state().qdot.allFinite());
  // omega_T > 0 turns the flagellum side about +t^1 and the head the other way (docs/model.md 1.9)
  const TrajectorySample& last = sim.trajectory().back();
  EXPECT_GT(last.tail_angle, 0.0);
  EXPECT_LE(last.head_angle, 0.0);
  // Far below the 15 deg buckling tilt: the off-axis hook bends and the head wobbles slightly.
  EXPECT_LT(units::radToDeg(last.flagellum_tilt), 5.0);
  const SummaryMetrics m = sim.summary();
  EXPECT_TRUE(std::isfinite(m.heading_change));
  EXPECT_LT(units::radToDeg(m.heading_change), 5.0);
  EXPECT_FALSE(m.buckled);
}

// The fastest motor a config accepts, started without a ramp: Newton follows it by subdividing
// steps (docs/model.md 1.10) or stops with a SolverFailure that names the time; the state is
// finite either way. Faster rates are refused by the config with the field and its range.
TEST(HelicalRun, FastestAcceptedMotorRateRunsOrFailsCleanlyAndFasterIsRefused) {
  const SimulationConfig c = loadSimulationConfig(
      shippedConfig("helical_robot.yaml"),
      {"motor.omega_rpm=10000", "motor.ramp_time=0", "robot.edge_length=0.015"});
  Simulation sim(c);
  try {
    sim.run(0.05);
    EXPECT_NEAR(sim.time(), 0.05, 1e-9);
  } catch (const SolverFailure& e) {
    EXPECT_NE(std::string(e.what()).find("t ="), std::string::npos) << e.what();
  }
  EXPECT_TRUE(sim.state().q.allFinite());
  EXPECT_TRUE(sim.state().qdot.allFinite());
  for (const TrajectorySample& s : sim.trajectory()) {
    ASSERT_TRUE(s.head_position.allFinite());
    ASSERT_TRUE(std::isfinite(s.omega_t));
  }
  try {
    loadSimulationConfig(shippedConfig("helical_robot.yaml"), {"motor.omega_rpm=20000"});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("motor.omega_rpm must be in [-10000, 10000] rpm"),
              std::string::npos)
        << e.what();
  }
}

TEST(HelicalRun, GimbalHoldsPivotAndHeadRoll) {
  const SimulationConfig c =
      loadSimulationConfig(shippedConfig("helical_gimbal.yaml"), {"motor.omega_rpm=30"});
  Simulation sim(c);
  sim.run(kShortRun);
  const RodNetwork& net = sim.network();
  EXPECT_TRUE(sim.state().q.allFinite());
  EXPECT_TRUE(nodePosition(sim.state().q, 0) == net.rest_positions[0]);
  EXPECT_EQ(sim.state().q(net.thetaIndex(0)), 0.0);
  EXPECT_GT(sim.trajectory().back().tail_angle, 0.0);
}

// docs/model.md 8.4.1: a left-handed helix turned by omega_T > 0 pushes the robot head first
// (toward -z), a right-handed one needs omega_T < 0, with the shipped RSS hydrodynamics.
TEST(HelicalRun, HandednessAndMotorSignDecidePusherMode) {
  struct Case {
    const char* handedness;
    const char* rpm;
    bool head_first;
  };
  for (const Case& k : {Case{"left", "60", true}, Case{"right", "-60", true},
                        Case{"right", "60", false}, Case{"left", "-60", false}}) {
    SCOPED_TRACE(std::string(k.handedness) + ", " + k.rpm + " rpm");
    const SimulationConfig c = loadSimulationConfig(
        shippedConfig("helical_robot.yaml"),
        {std::string("robot.handedness=") + k.handedness, std::string("motor.omega_rpm=") + k.rpm,
         "motor.ramp_time=0.2", "simulation.duration=1.5"});
    Simulation sim(c);
    sim.run(c.duration);
    const double forward = -sim.trajectory().back().head_position.z();  // along -t^0 at rest
    EXPECT_EQ(forward > 0.0, k.head_first) << "x_1 moved by " << -forward << " m along +z";
    EXPECT_GT(std::abs(forward), 1e-4);  // a clear displacement, not round-off
  }
}

// flagella_run writes the helical fields into summary.json.
TEST(HelicalRun, SummaryJsonHasTheHelicalFields) {
  ASSERT_TRUE(fs::exists(kRunExe)) << kRunExe << " is not built (make flagella_run)";
  const TempDir out;
  const std::string command = std::string(kRunExe) + " run " + shippedConfig("helical_robot.yaml") +
                              " --omega-rpm 30 --duration 0.3 --quiet --out " +
                              out.path().string() + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
  const std::string json = testing::readTextFile(out.path() / "summary.json");
  for (const char* key :
       {"\"robot\": \"helical\"", "\"pitch_count\": 3.5", "\"heading_change_deg\":",
        "\"flagellum_tilt_max_deg\":", "\"buckled\": false", "\"buckling_tilt_deg\": 15"})
    EXPECT_TRUE(contains(json, key)) << key << " missing in\n" << json;
  EXPECT_FALSE(contains(json, "n_tails")) << json;
}

}  // namespace
}  // namespace flagella
