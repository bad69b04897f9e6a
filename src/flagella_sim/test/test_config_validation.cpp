// Tests of config validation: every user mistake in a YAML file, an override or a named
// parameter is rejected with a ConfigError whose message names the full dotted field and, for
// range errors, the allowed range "[min, max]". Nothing is ever clamped.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/core/yaml_fields.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/effects/interface_lateral_force.h"
#include "flagella_sim/simulation/problem_size.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr char kDesign1[] = "granular_design1.yaml";
constexpr char kInterfaceRobot[] = "interface_robot.yaml";
constexpr int kMinShippedConfigs = 4;
constexpr double kExactTol = 1e-12;
// Defaults of the interface viscosity profile (simulation_config.cpp): h = 0.7 R, k = 20.
constexpr double kDefaultOnsetOverRadius = 0.7;
constexpr double kDefaultSharpness = 20.0;
// Range of the head drag prefactors declared by StokesHeadDrag.
constexpr double kHeadDragMax = 1e4;

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

/// A fresh directory under the system temp dir, removed with everything in it at scope exit.

/// The sections of a small valid config; tests replace one section at a time.
struct ConfigSections {
  std::string robot =
      "robot:\n"
      "  n_tails: 2\n"
      "  tail_length: 0.1\n"
      "  tail_edges: 10\n"
      "  head_radius: 0.02\n";
  std::string medium =
      "medium:\n"
      "  viscosity: 2.0\n"
      "  up: [0, 1, 0]\n";
  std::string effects =
      "effects:\n"
      "  rft:\n"
      "    log_form: \"2L/r0\"\n"
      "  stokes_head:\n"
      "    C_t: 2.0\n"
      "    C_r: 0.5\n";
  std::string motor =
      "motor:\n"
      "  omega_rpm: 60\n";
  std::string simulation =
      "simulation:\n"
      "  dt: 0.01\n"
      "  duration: 1\n";
  std::string solver =
      "solver:\n"
      "  max_iterations: 25\n";
  std::string extra;

  std::string text() const {
    return robot + medium + effects + motor + simulation + solver + extra;
  }
};

std::string configErrorOf(const std::function<void()>& fn) {
  return testing::errorMessageOf<ConfigError>(fn);
}

std::string loadError(const std::string& path, const std::vector<std::string>& overrides = {}) {
  return configErrorOf([&] { loadSimulationConfig(path, overrides); });
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// True if the message says "<field> must be in [<min>, <max>]" (the rangeMessage wording).
bool namesFieldAndRange(const std::string& message, const std::string& field) {
  const std::regex pattern(std::regex_replace(field, std::regex(R"([.\[\]])"), R"(\$&)") +
                           R"( must be in \[[^,\]]+, [^\]]+\])");
  return std::regex_search(message, pattern);
}

// ---------------------------------------------------------------------------------------------
// Shipped configs and the baseline
// ---------------------------------------------------------------------------------------------

TEST(ShippedConfigs, EveryConfigLoadsAndBuildsASimulation) {
  int count = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(kConfigDir)) {
    if (entry.path().extension() != ".yaml") continue;
    ++count;
    SCOPED_TRACE(entry.path().string());
    SimulationConfig config;
    ASSERT_NO_THROW(config = loadSimulationConfig(entry.path().string()));
    EXPECT_EQ(config.source, entry.path().string());
    EXPECT_FALSE(config.effects.empty());
    EXPECT_GT(config.dt, 0.0);
    ASSERT_NO_THROW({
      Simulation sim(config);
      EXPECT_FALSE(sim.parameterNames().empty());
    });
  }
  EXPECT_GE(count, kMinShippedConfigs);
}

TEST(ConfigValidation, AnOutputIntervalBelowTheStepNamesBothFields) {
  // `flagella_run --dt 1` on a config with output_interval 0.1: the message names the step too,
  // not only a range for output_interval that the user never set.
  const TempDir dir;
  ConfigSections s;
  s.simulation = "simulation:\n  dt: 0.5\n  duration: 1\n  output_interval: 0.1\n";
  const std::string message = loadError(dir.write("short.yaml", s.text()));
  EXPECT_TRUE(contains(message, "output_interval")) << message;
  EXPECT_TRUE(contains(message, "simulation.dt (0.5 s)")) << message;
  EXPECT_TRUE(contains(message, "must be at least")) << message;
  s.simulation = "simulation:\n  dt: 0.1\n  duration: 1\n  output_interval: 0.1\n";
  EXPECT_NO_THROW(loadSimulationConfig(dir.write("equal.yaml", s.text())));
}

TEST(ConfigBaseline, SmallConfigLoadsWithItsValues) {
  const TempDir dir;
  const SimulationConfig c = loadSimulationConfig(dir.write("ok.yaml", ConfigSections().text()));
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().n_tails, 2);
  EXPECT_DOUBLE_EQ(c.robotGeometry<MultiTailGeometry>().tail_length, 0.1);
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().tail_edges, 10);
  EXPECT_DOUBLE_EQ(c.medium.viscosity(), 2.0);
  EXPECT_NEAR(c.motor.omega, units::rpmToRadPerSec(60.0), kExactTol);
  ASSERT_EQ(c.effects.size(), 2u);
  EXPECT_NO_THROW(Simulation{c});
}

// ---------------------------------------------------------------------------------------------
// Unknown fields
// ---------------------------------------------------------------------------------------------

TEST(UnknownField, TopLevelIsRejectedWithTheAllowedSections) {
  const TempDir dir;
  ConfigSections s;
  s.extra = "simulaton:\n  dt: 0.01\n";
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(contains(msg, "unknown field 'simulaton'")) << msg;
  for (const char* section : {"robot", "medium", "effects", "motor", "simulation", "solver"})
    EXPECT_TRUE(contains(msg, section)) << "allowed list lacks " << section << ": " << msg;
}

TEST(UnknownField, InRobotIsRejectedWithTheDottedNameAndAllowedNames) {
  const TempDir dir;
  ConfigSections s;
  s.robot += "  n_tail: 3\n";
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(contains(msg, "'robot.n_tail'")) << msg;
  EXPECT_TRUE(contains(msg, "allowed")) << msg;
  for (const char* name : {"n_tails", "tail_length", "tail_edges", "poisson_ratio"})
    EXPECT_TRUE(contains(msg, name)) << "allowed list lacks " << name << ": " << msg;
  // The line of the offending key is given (robot section starts at line 1, n_tail is line 6).
  EXPECT_TRUE(contains(msg, "line 6")) << msg;
}

TEST(UnknownField, InMediumAndNestedProfileAreRejected) {
  const TempDir dir;
  ConfigSections s;
  s.medium += "  viscosty: 1.0\n";
  EXPECT_TRUE(contains(loadError(dir.write("a.yaml", s.text())), "'medium.viscosty'"));
  ConfigSections p;
  p.medium += "  interface_profile:\n    enabled: true\n    sharpnes: 3\n";
  const std::string msg = loadError(dir.write("b.yaml", p.text()));
  EXPECT_TRUE(contains(msg, "'medium.interface_profile.sharpnes'")) << msg;
  EXPECT_TRUE(contains(msg, "sharpness")) << msg;
}

TEST(UnknownField, EffectParameterIsRejectedWithItsKnownNames) {
  const TempDir dir;
  ConfigSections s;
  s.effects += "    C_tt: 1.0\n";  // a typo inside effects.stokes_head
  // Effect parameters are validated while loading, so the message carries the file name too.
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(contains(msg, "effects.stokes_head.C_tt")) << msg;
  EXPECT_TRUE(contains(msg, "C_t")) << msg;
  EXPECT_TRUE(contains(msg, "C_r")) << msg;
}

// The structural options ("mode", "log_form", "use_interface_profile") belong to one effect
// each; written under another effect they must be rejected like any other unknown field.
TEST(UnknownField, StructuralOptionOfAnotherEffectIsRejected) {
  const TempDir dir;
  ConfigSections s;
  s.effects += "    mode: integrated\n";  // "mode" belongs to interface_lateral_force
  const std::string path = dir.write("c.yaml", s.text());
  const std::string msg = configErrorOf([&] { Simulation sim(loadSimulationConfig(path)); });
  EXPECT_TRUE(contains(msg, "effects.stokes_head.mode")) << msg;

  ConfigSections g;
  g.effects += "  gravity:\n    log_form: \"L/r0\"\n";  // "log_form" belongs to rft
  const std::string gpath = dir.write("g.yaml", g.text());
  const std::string gmsg = configErrorOf([&] { Simulation sim(loadSimulationConfig(gpath)); });
  EXPECT_TRUE(contains(gmsg, "effects.gravity.log_form")) << gmsg;
}

TEST(UnknownEffect, IsRejectedWithTheKnownEffectNames) {
  const TempDir dir;
  ConfigSections s;
  s.effects += "  propeller:\n    C: 1.0\n";
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(contains(msg, "effects.propeller")) << msg;
  ASSERT_FALSE(registeredEffectNames().empty());
  for (const std::string& name : registeredEffectNames())
    EXPECT_TRUE(contains(msg, name)) << "known list lacks " << name << ": " << msg;
}

// ---------------------------------------------------------------------------------------------
// Out-of-range values: field name and "[min, max]" in the message, for files and overrides
// ---------------------------------------------------------------------------------------------

struct RangeCase {
  std::string override_text;
  std::string field;
  std::string expected_fragment;  ///< e.g. the exact range or the rejected value
};

TEST(OutOfRange, OverridesAreRejectedNamingFieldAndRange) {
  const std::vector<RangeCase> cases{
      {"robot.n_tails=0", "robot.n_tails", "[1, "},
      {"robot.n_tails=13", "robot.n_tails", "got 13"},
      {"robot.tail_length=-0.1", "robot.tail_length", "got -0.1"},
      {"robot.tail_radius=0", "robot.tail_radius", "got 0"},
      {"robot.youngs_modulus=-1e6", "robot.youngs_modulus", "got -1e+06"},
      {"robot.poisson_ratio=0.7", "robot.poisson_ratio", "[0, 0.5]"},
      {"robot.poisson_ratio=-0.1", "robot.poisson_ratio", "[0, 0.5]"},
      {"robot.tail_length=.nan", "robot.tail_length", "got nan"},
      {"robot.tail_length=.inf", "robot.tail_length", "got inf"},
      {"simulation.dt=0", "simulation.dt", "got 0"},
      {"simulation.dt=-0.01", "simulation.dt", "got -0.01"},
      {"simulation.dt=.nan", "simulation.dt", "got nan"},
      {"simulation.duration=-1", "simulation.duration", "got -1"},
      {"motor.omega_rpm=1e5", "motor.omega_rpm", "got 100000"},
      {"motor.omega_rpm=-1e5", "motor.omega_rpm", "got -100000"},
      {"motor.ramp_time=-1", "motor.ramp_time", "got -1"},
      {"medium.viscosity=-1", "medium.viscosity", "got -1"},
      {"solver.max_iterations=0", "solver.max_iterations", "got 0"},
      {"solver.residual_tolerance=0", "solver.residual_tolerance", "got 0"},
      {"solver.residual_tolerance=1e-14", "solver.residual_tolerance", "[1e-10, 1]"},
      {"solver.stagnation_updates=1", "solver.stagnation_updates", "[2, 12]"},
      {"solver.stagnation_updates=13", "solver.stagnation_updates", "got 13"},
  };
  const std::string path = shippedConfig(kDesign1);
  for (const RangeCase& rc : cases) {
    SCOPED_TRACE(rc.override_text);
    const std::string msg = loadError(path, {rc.override_text});
    EXPECT_TRUE(namesFieldAndRange(msg, rc.field)) << msg;
    EXPECT_TRUE(contains(msg, rc.expected_fragment)) << msg;
    EXPECT_TRUE(contains(msg, path)) << "message does not name the file: " << msg;
  }
}

TEST(OutOfRange, SmallestResidualToleranceIsMetByTheShippedRobots) {
  // The declared range is one the solver can meet: at its lower end every step converges
  // (round-off stalls Newton only near 1e-12).
  for (const char* name : {kDesign1, kInterfaceRobot}) {
    SCOPED_TRACE(name);
    Simulation sim(loadSimulationConfig(shippedConfig(name), {"solver.residual_tolerance=1e-10"}));
    EXPECT_NO_THROW(sim.run(0.3));
    EXPECT_EQ(sim.sample().subdivided_steps, 0);
  }
}

TEST(OutOfRange, InFileValueNamesFieldRangeAndLine) {
  const TempDir dir;
  ConfigSections s;
  s.robot += "  poisson_ratio: 0.7\n";  // line 6
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(namesFieldAndRange(msg, "robot.poisson_ratio")) << msg;
  EXPECT_TRUE(contains(msg, "[0, 0.5]")) << msg;
  EXPECT_TRUE(contains(msg, "got 0.7")) << msg;
  EXPECT_TRUE(contains(msg, "line 6")) << msg;
}

TEST(OutOfRange, NanAndZeroStepInFile) {
  const TempDir dir;
  ConfigSections nan_case;
  nan_case.robot = "robot:\n  tail_length: .nan\n";
  const std::string nan_msg = loadError(dir.write("nan.yaml", nan_case.text()));
  EXPECT_TRUE(namesFieldAndRange(nan_msg, "robot.tail_length")) << nan_msg;
  EXPECT_TRUE(contains(nan_msg, "nan")) << nan_msg;

  ConfigSections dt_case;
  dt_case.simulation = "simulation:\n  dt: 0\n";
  const std::string dt_msg = loadError(dir.write("dt.yaml", dt_case.text()));
  EXPECT_TRUE(namesFieldAndRange(dt_msg, "simulation.dt")) << dt_msg;

  ConfigSections n_case;
  n_case.robot = "robot:\n  n_tails: 0\n";
  EXPECT_TRUE(namesFieldAndRange(loadError(dir.write("n.yaml", n_case.text())), "robot.n_tails"));
}

TEST(OutOfRange, PerTailListEntryNamesTheIndex) {
  const std::string msg =
      loadError(shippedConfig(kDesign1), {"robot.tail_length_scale=[1.0, 100.0]"});
  EXPECT_TRUE(namesFieldAndRange(msg, "robot.tail_length_scale[1]")) << msg;
}

// ---------------------------------------------------------------------------------------------
// Wrong types
// ---------------------------------------------------------------------------------------------

struct TypeCase {
  std::string override_text;
  std::string field;
};

TEST(WrongType, ScalarsAndSectionsNameTheField) {
  const std::vector<TypeCase> cases{
      {"robot.tail_length=abc", "robot.tail_length"},
      {"robot.n_tails=2.5", "robot.n_tails"},
      {"robot.n_tails=two", "robot.n_tails"},
      {"robot.tail_length=[1, 2]", "robot.tail_length"},
      {"medium.up=1", "medium.up"},
      {"medium.up=[0, 1]", "medium.up"},
      {"robot.tail_length_scale=1.0", "robot.tail_length_scale"},
      {"effects.rft.use_interface_profile=maybe", "effects.rft.use_interface_profile"},
      {"motor.mode=sideways", "motor.mode"},
      {"effects.rft.log_form=r0", "effects.rft.log_form"},
      {"robot=5", "robot"},
  };
  const std::string path = shippedConfig(kDesign1);
  for (const TypeCase& tc : cases) {
    SCOPED_TRACE(tc.override_text);
    const std::string msg = loadError(path, {tc.override_text});
    EXPECT_TRUE(contains(msg, tc.field)) << msg;
  }
}

TEST(WrongType, ChoiceListsTheAllowedValues) {
  const std::string msg = loadError(shippedConfig(kDesign1), {"motor.mode=sideways"});
  EXPECT_TRUE(contains(msg, "motor.mode")) << msg;
  EXPECT_TRUE(contains(msg, "constant")) << msg;
  EXPECT_TRUE(contains(msg, "binary")) << msg;
  EXPECT_TRUE(contains(msg, "sideways")) << msg;
}

// A non-number inside a list (or a list where a name is expected) must still name the field,
// not surface a bare yaml-cpp "bad conversion".
TEST(WrongType, BadListElementsAndNonScalarChoicesNameTheField) {
  const std::vector<TypeCase> cases{
      {"medium.up=[0, up, 0]", "medium.up"},
      {"medium.gravity=[0, -9.81, g]", "medium.gravity"},
      {"robot.tail_length_scale=[1.0, x]", "robot.tail_length_scale"},
      {"motor.mode=[constant]", "motor.mode"},
  };
  const std::string path = shippedConfig(kDesign1);
  for (const TypeCase& tc : cases) {
    SCOPED_TRACE(tc.override_text);
    const std::string msg = loadError(path, {tc.override_text});
    EXPECT_TRUE(contains(msg, tc.field)) << msg;
  }
}

// ---------------------------------------------------------------------------------------------
// Structural rules
// ---------------------------------------------------------------------------------------------

TEST(Structure, TailEdgesAndTailEdgeLengthAreExclusive) {
  const TempDir dir;
  ConfigSections s;
  s.robot += "  tail_edge_length: 0.004\n";  // tail_edges is already given
  const std::string msg = loadError(dir.write("c.yaml", s.text()));
  EXPECT_TRUE(contains(msg, "robot.tail_edges")) << msg;
  EXPECT_TRUE(contains(msg, "robot.tail_edge_length")) << msg;
}

TEST(Structure, TailEdgeLengthAloneSetsTheEdgeCount) {
  constexpr double kEdgeLength = 0.004;
  const TempDir dir;
  ConfigSections s;
  s.robot = "robot:\n  tail_length: 0.1\n  tail_edge_length: 0.004\n";
  const SimulationConfig c = loadSimulationConfig(dir.write("c.yaml", s.text()));
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().tail_edges,
            static_cast<int>(std::lround(0.1 / kEdgeLength)));
}

TEST(Structure, PerTailListsNeedOneEntryPerTail) {
  const std::string path = shippedConfig(kDesign1);  // n_tails = 2
  for (const char* field : {"robot.tail_length_scale", "robot.tail_stiffness_scale"}) {
    SCOPED_TRACE(field);
    const std::string three = std::string(field) + "=[1.0, 1.0, 1.0]";
    const std::string msg = loadError(path, {three});
    EXPECT_TRUE(contains(msg, field)) << msg;
    EXPECT_TRUE(contains(msg, "n_tails = 2")) << msg;
    // The same list is valid with three tails.
    SimulationConfig c;
    ASSERT_NO_THROW(c = loadSimulationConfig(path, {three, "robot.n_tails=3"}));
    EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().n_tails, 3);
  }
  const SimulationConfig ok = loadSimulationConfig(path, {"robot.tail_length_scale=[0.5, 2.0]"});
  ASSERT_EQ(ok.robotGeometry<MultiTailGeometry>().tail_length_scale.size(), 2u);
  EXPECT_DOUBLE_EQ(ok.robotGeometry<MultiTailGeometry>().tail_length_scale[1], 2.0);
}

TEST(Structure, NonMapRootIsRejected) {
  const TempDir dir;
  const std::string msg = loadError(dir.write("list.yaml", "- robot\n- medium\n"));
  EXPECT_TRUE(contains(msg, "map")) << msg;
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

TEST(ConfigFile, YamlSyntaxErrorGivesFileAndLine) {
  const TempDir dir;
  const std::string text =
      "robot:\n"
      "  n_tails: 2\n"
      "medium:\n"
      "  up: [0, 1, 0\n"  // unclosed flow sequence
      "motor:\n"
      "  omega_rpm: 60\n";
  const std::string path = dir.write("broken.yaml", text);
  const std::string msg = loadError(path);
  EXPECT_TRUE(contains(msg, path)) << msg;
  EXPECT_TRUE(std::regex_search(msg, std::regex(R"(line [0-9]+)"))) << msg;
}

TEST(ConfigFile, BadIndentationGivesTheLine) {
  const TempDir dir;
  const std::string text =
      "robot:\n"
      "  n_tails: 2\n"
      "   tail_length: 0.1\n";  // line 3: inconsistent indentation
  const std::string path = dir.write("indent.yaml", text);
  const std::string msg = loadError(path);
  EXPECT_TRUE(contains(msg, path)) << msg;
  EXPECT_TRUE(contains(msg, "line 3")) << msg;
}

TEST(ConfigFile, MissingFileIsAConfigErrorNamingThePath) {
  const TempDir dir;
  const std::string path = dir.write("exists.yaml", "") + ".missing";
  const std::string msg = loadError(path);
  EXPECT_TRUE(contains(msg, path)) << msg;
  EXPECT_TRUE(contains(msg, "cannot open")) << msg;
}

// ---------------------------------------------------------------------------------------------
// Overrides
// ---------------------------------------------------------------------------------------------

TEST(Overrides, ApplyToExistingAndNewFields) {
  const std::string path = shippedConfig(kDesign1);
  const SimulationConfig base = loadSimulationConfig(path);
  ASSERT_EQ(base.robotGeometry<MultiTailGeometry>().n_tails, 2);
  const SimulationConfig c = loadSimulationConfig(
      path, {"robot.n_tails=3", "motor.omega_rpm=60", "medium.up=[0, 0, 2]",
             "solver.max_iterations=7", "simulation.duration=1.5", "robot.spoke_phase_deg=90"});
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().n_tails, 3);
  EXPECT_NEAR(c.motor.omega, units::rpmToRadPerSec(60.0), kExactTol);
  EXPECT_NEAR((c.medium.up - Vec3::UnitZ()).norm(), 0.0, kExactTol);  // normalised
  EXPECT_EQ(c.solver.max_iterations, 7);
  EXPECT_DOUBLE_EQ(c.duration, 1.5);
  EXPECT_NEAR(c.robotGeometry<MultiTailGeometry>().spoke_phase, M_PI / 2, kExactTol);
  // Untouched fields keep the file's values.
  EXPECT_DOUBLE_EQ(c.robotGeometry<MultiTailGeometry>().tail_length,
                   base.robotGeometry<MultiTailGeometry>().tail_length);
  EXPECT_DOUBLE_EQ(c.medium.viscosity(), base.medium.viscosity());
}

TEST(Overrides, LaterOverridesWinAndCreateSections) {
  const TempDir dir;
  ConfigSections s;
  s.solver = "";  // no solver section in the file
  const std::string path = dir.write("c.yaml", s.text());
  const SimulationConfig c = loadSimulationConfig(
      path,
      {"robot.n_tails=3", "robot.n_tails=4", "solver.max_iterations=9", "effects.gravity={}"});
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().n_tails, 4);
  EXPECT_EQ(c.solver.max_iterations, 9);
  bool has_gravity = false;
  for (const EffectSpec& e : c.effects) has_gravity = has_gravity || e.name == "gravity";
  EXPECT_TRUE(has_gravity);
}

TEST(Overrides, ApplyOverrideOnATree) {
  YAML::Node root = YAML::Load("robot:\n  n_tails: 2\n");
  applyOverride(root, "robot.n_tails=3");
  applyOverride(root, "motor.omega_rpm=12.5");
  EXPECT_EQ(root["robot"]["n_tails"].as<int>(), 3);
  EXPECT_DOUBLE_EQ(root["motor"]["omega_rpm"].as<double>(), 12.5);
}

TEST(Overrides, MalformedAssignmentsAreRejected) {
  const std::string path = shippedConfig(kDesign1);
  for (const std::string bad :
       {"robot.n_tails", "=3", "", "robot.n_tails.x=3", "robot.n_tails=[1"}) {
    SCOPED_TRACE("override '" + bad + "'");
    const std::string msg = loadError(path, {bad});
    EXPECT_TRUE(contains(msg, "override")) << msg;
  }
  const std::string msg = loadError(path, {"robot.n_tails"});
  EXPECT_TRUE(contains(msg, "section.field=value")) << msg;
}

TEST(Overrides, NullMeansTheDefault) {
  // docs: a field set to null takes its default, for every kind of field.
  const std::string path = shippedConfig(kDesign1);
  const SimulationConfig plain = loadSimulationConfig(path, {"robot.tail_edge_length=null"});
  EXPECT_EQ(plain.robotGeometry<MultiTailGeometry>().tail_edges,
            loadSimulationConfig(path).robotGeometry<MultiTailGeometry>().tail_edges);
  EXPECT_EQ(loadSimulationConfig(path, {"motor.omega_rpm=~"}).motor.omega, 0.0);
  EXPECT_EQ(loadSimulationConfig(path, {"motor.mode=null"}).motor.mode, "constant");
}

TEST(Overrides, ModeSpecificFieldsNameTheModeTheyNeed) {
  // Back to the default mode, the binary schedule's durations no longer apply: the error says
  // so instead of calling them unknown.
  const std::string path = shippedConfig("interface_path_planning.yaml");
  const std::string msg = loadError(path, {"motor.mode=null"});
  EXPECT_TRUE(contains(msg, "motor.positive_duration applies only to motor.mode: binary")) << msg;
  EXPECT_TRUE(contains(msg, "the default")) << msg;
}

TEST(Overrides, ErrorsBlameTheOverrideNotTheFile) {
  const std::string path = shippedConfig(kDesign1);
  const std::string msg = loadError(path, {"motor.omega_rpm=1e5"});
  EXPECT_EQ(msg.rfind("override 'motor.omega_rpm=1e5' (on " + path + "): motor.omega_rpm", 0), 0u)
      << msg;
  // The last override of a field is the one to blame; other fields still blame the file.
  const std::string last = loadError(path, {"motor.omega_rpm=1e5", "motor.omega_rpm=2e5"});
  EXPECT_TRUE(contains(last, "override 'motor.omega_rpm=2e5'")) << last;
  const TempDir dir;
  const std::string bad = dir.write("bad.yaml", "motor:\n  omega_rpm: 1e5\n");
  const std::string in_file = loadError(bad, {"motor.ramp_time=1"});
  EXPECT_EQ(in_file.rfind(bad + ": motor.omega_rpm", 0), 0u) << in_file;
  EXPECT_TRUE(contains(in_file, "line 2")) << in_file;
}

TEST(ConfigValidation, EffectKeysWithoutValueAreRefusedUnlessKnown) {
  // `bogus:` under an effect, and a decimal comma in a flow map ({C_t: 1,5} reads as C_t: 1 and
  // a key 5 without a value), were ignored; a known parameter without a value keeps its default.
  const TempDir dir;
  ConfigSections empty_key;
  empty_key.effects += "    bogus:\n";
  const std::string msg = loadError(dir.write("empty_key.yaml", empty_key.text()));
  EXPECT_TRUE(contains(msg, "unknown parameter 'effects.stokes_head.bogus'")) << msg;
  EXPECT_TRUE(contains(msg, "known: C_t, C_r")) << msg;
  ConfigSections comma;
  comma.effects = "effects:\n  stokes_head: {C_t: 1,5, C_r: 0.039}\n";
  const std::string comma_msg = loadError(dir.write("comma.yaml", comma.text()));
  EXPECT_TRUE(contains(comma_msg, "unknown parameter 'effects.stokes_head.5'")) << comma_msg;
  ConfigSections known_null;
  known_null.effects += "    head_radius:\n";
  const SimulationConfig c = loadSimulationConfig(dir.write("known_null.yaml", known_null.text()));
  EXPECT_FALSE(c.effects.empty());
}

TEST(Overrides, HugeValuesAreQuotedAbbreviated) {
  const std::string huge(100000, 'x');
  const std::string msg = loadError(shippedConfig(kDesign1), {"motor.mode=" + huge});
  EXPECT_LT(msg.size(), 600u) << msg.substr(0, 600);
  EXPECT_TRUE(contains(msg, "(100000 characters)")) << msg.substr(0, 600);
  EXPECT_TRUE(contains(msg, "motor.mode must be one of: constant, binary")) << msg.substr(0, 600);
}

TEST(Overrides, HugeKeysAreQuotedAbbreviated) {
  // Unknown keys and override paths were quoted whole (a 100 kB message, which fuzz/fuzz_config
  // rejects); like values they are abbreviated, still under their dotted field.
  const std::string huge(100000, 'k');
  const TempDir dir;
  ConfigSections in_robot;
  in_robot.robot += "  ? " + huge + "\n  : 1\n";
  ConfigSections in_effect;
  in_effect.effects += "    ? " + huge + "\n    : 1\n";
  ConfigSections effect;
  effect.effects += "  ? " + huge + "\n  : {}\n";
  ConfigSections in_profile;
  in_profile.medium += "  interface_profile:\n    ? " + huge + "\n    : 1\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {in_robot.text(), "unknown field 'robot.kkk"},
      {in_effect.text(), "unknown parameter 'effects.stokes_head.kkk"},
      {effect.text(), "unknown effect 'effects.kkk"},
      {in_profile.text(), "unknown field 'medium.interface_profile.kkk"},
      {"? " + huge + "\n: 1\n", "unknown field 'kkk"}};
  for (const auto& [text, wording] : cases) {
    const std::string msg = loadError(dir.write("huge_key.yaml", text));
    EXPECT_LT(msg.size(), 1000u) << msg.substr(0, 1000);
    EXPECT_TRUE(contains(msg, wording)) << msg.substr(0, 1000);
    EXPECT_TRUE(contains(msg, "... (100000 characters)")) << msg.substr(0, 1000);
  }
  const std::string path = shippedConfig(kDesign1);
  for (const std::string& override :
       {"robot." + huge + "=1", huge + ".x=[1", "robot.n_tails." + huge + "=1"}) {
    const std::string msg = loadError(path, {override});
    EXPECT_LT(msg.size(), 1000u) << msg.substr(0, 1000);
    EXPECT_TRUE(contains(msg, "characters)")) << msg.substr(0, 1000);
  }
}

TEST(Overrides, OnAConfigThatIsNotAMapNameTheOverride) {
  // yaml-cpp's own error for a key on a scalar or list quoted the key whole.
  const TempDir dir;
  for (const std::string text : {"5\n", "[1, 2]\n"}) {
    const std::string msg = loadError(dir.write("not_a_map.yaml", text), {"robot.n_tails=3"});
    EXPECT_TRUE(contains(msg, "override 'robot.n_tails=3': the config is not a map of sections"))
        << msg;
  }
}

TEST(Overrides, ErrorsNamingAnOverriddenFieldBlameTheOverride) {
  // An unknown field given by --set, and a rule between two fields broken by an override,
  // blamed the config file.
  const std::string path = shippedConfig("helical_robot.yaml");
  const std::string typo = loadError(path, {"robot.filament_radus=1e-3"});
  EXPECT_EQ(typo.rfind("override 'robot.filament_radus=1e-3' (on " + path + "): ", 0), 0u) << typo;
  const std::string rule = loadError(path, {"motor.omega_rpm=5", "robot.filament_radius=0.02"});
  EXPECT_EQ(rule.rfind("override 'robot.filament_radius=0.02' (on " + path + "): robot.pitch", 0),
            0u)
      << rule;
  // A prefix of a longer name is not a mention: robot.pitch is not robot.pitch_count.
  const std::string other = loadError(path, {"robot.pitch=0.001", "robot.pitch_count=3"});
  EXPECT_TRUE(contains(other, "override 'robot.pitch=0.001'")) << other;
}

TEST(ProblemSize, EstimateCountsTheNodesTheBuilderMakes) {
  // The estimate is made before building: it must agree with what the builder then makes.
  for (const char* name : {"helical_gimbal.yaml", "helical_shore22.yaml"}) {
    for (const std::string pitches : {"2.5", "3.5", "4.5"}) {
      const SimulationConfig c =
          loadSimulationConfig(shippedConfig(name), {"robot.pitch_count=" + pitches});
      const ProblemSize size = estimateProblemSize(c);
      const Simulation sim(c);
      EXPECT_NEAR(size.nodes, sim.network().numNodes(), 1) << name << " " << pitches;
      EXPECT_NEAR(size.dofs, sim.network().ndof(), 4) << name << " " << pitches;
    }
  }
  // No dense block: nothing estimated, nothing refused.
  EXPECT_EQ(estimateProblemSize(loadSimulationConfig(shippedConfig(kDesign1))).nodes, 0);
}

TEST(ProblemSize, HelixInMetresIsRefusedWithItsFiguresAndTheOverride) {
  // Millimetres given as metres: thousands of nodes; the dense model would need gigabytes or
  // tens of seconds per step. Refused while loading, naming the override and the way out.
  const std::string path = shippedConfig("helical_gimbal.yaml");
  for (const std::string bad : {"robot.helix_radius=2.5", "robot.pitch=2.5"}) {
    const std::string msg = loadError(path, {bad});
    EXPECT_EQ(msg.rfind("override '" + bad + "'", 0), 0u) << msg;
    EXPECT_TRUE(contains(msg, "nodes, dense blocks")) << msg;
    EXPECT_TRUE(contains(msg, "per factorisation")) << msg;
    EXPECT_TRUE(contains(msg, "solver.size_check=false")) << msg;
    const SimulationConfig allowed = loadSimulationConfig(path, {bad, "solver.size_check=false"});
    EXPECT_GT(estimateProblemSize(allowed).seconds_per_update, kMaxSecondsPerUpdate) << bad;
  }
}

TEST(Overrides, UnknownFieldViaOverrideIsRejected) {
  const std::string msg = loadError(shippedConfig(kDesign1), {"robot.n_tail=3"});
  EXPECT_TRUE(contains(msg, "'robot.n_tail'")) << msg;
  EXPECT_TRUE(contains(msg, "n_tails")) << msg;
}

// ---------------------------------------------------------------------------------------------
// Effect parameters and named parameters of a Simulation
// ---------------------------------------------------------------------------------------------

TEST(EffectParameters, OutOfRangeIsRejectedWhileLoading) {
  const std::string path = shippedConfig(kDesign1);
  const std::string msg = loadError(path, {"effects.stokes_head.C_t=-1"});
  EXPECT_TRUE(namesFieldAndRange(msg, "effects.stokes_head.C_t")) << msg;
  EXPECT_TRUE(contains(msg, "got -1")) << msg;
  EXPECT_TRUE(contains(msg, "granular_design1.yaml")) << msg;
  EXPECT_TRUE(namesFieldAndRange(loadError(path, {"effects.stokes_head.C_r=2e4"}),
                                 "effects.stokes_head.C_r"));
}

TEST(EffectParameters, OutOfRangeIsRejectedAtSimulationConstruction) {
  // A config assembled in code (not loaded) is validated when the Simulation is built.
  SimulationConfig c = loadSimulationConfig(shippedConfig(kDesign1));
  for (EffectSpec& e : c.effects)
    if (e.name == "stokes_head") e.parameters.emplace_back("C_t", -1.0);
  const std::string msg = configErrorOf([&] { Simulation sim(c); });
  EXPECT_TRUE(namesFieldAndRange(msg, "effects.stokes_head.C_t")) << msg;
}

TEST(EffectParameters, NonFiniteIsRejectedNamingTheField) {
  const std::string path = shippedConfig(kDesign1);
  const std::string msg = configErrorOf(
      [&] { Simulation sim(loadSimulationConfig(path, {"effects.stokes_head.C_t=.nan"})); });
  EXPECT_TRUE(contains(msg, "effects.stokes_head.C_t")) << msg;
  EXPECT_TRUE(contains(msg, "nan")) << msg;
}

class SimulationParameters : public ::testing::Test {
 protected:
  SimulationParameters() : sim_(loadSimulationConfig(shippedConfig(kDesign1))) {}
  Simulation sim_;
};

TEST_F(SimulationParameters, ReadAndWriteByName) {
  constexpr double kViscosity = 3.5;
  constexpr double kCt = 1.25;
  EXPECT_DOUBLE_EQ(sim_.parameter("medium.viscosity"), 6.828);
  EXPECT_DOUBLE_EQ(sim_.parameter("effects.stokes_head.C_t"), 2.420);
  sim_.setParameter("medium.viscosity", kViscosity);
  sim_.setParameter("effects.stokes_head.C_t", kCt);
  EXPECT_EQ(sim_.parameter("medium.viscosity"), kViscosity);
  EXPECT_EQ(sim_.parameter("effects.stokes_head.C_t"), kCt);
  // Every listed name is readable and can be written back with its own value.
  for (const std::string& name : sim_.parameterNames()) {
    SCOPED_TRACE(name);
    double value = 0.0;
    ASSERT_NO_THROW(value = sim_.parameter(name));
    EXPECT_NO_THROW(sim_.setParameter(name, value));
    EXPECT_EQ(sim_.parameter(name), value);
  }
}

TEST_F(SimulationParameters, BoundsAreAcceptedExactly) {
  sim_.setParameter("effects.stokes_head.C_t", 0.0);
  EXPECT_EQ(sim_.parameter("effects.stokes_head.C_t"), 0.0);
  sim_.setParameter("effects.stokes_head.C_t", kHeadDragMax);
  EXPECT_EQ(sim_.parameter("effects.stokes_head.C_t"), kHeadDragMax);
}

TEST_F(SimulationParameters, UnknownNamesAreRejected) {
  const std::string bogus = configErrorOf([&] { sim_.setParameter("medium.bogus", 1.0); });
  EXPECT_TRUE(contains(bogus, "medium.bogus")) << bogus;
  EXPECT_TRUE(contains(bogus, "viscosity")) << bogus;  // the known names

  const std::string off = configErrorOf([&] { sim_.setParameter("effects.gravity.scale", 1.0); });
  EXPECT_TRUE(contains(off, "gravity")) << off;  // not switched on in design 1

  const std::string typo = configErrorOf([&] { sim_.setParameter("effects.stokes_head.Ct", 1.0); });
  EXPECT_TRUE(contains(typo, "effects.stokes_head.Ct")) << typo;
  EXPECT_TRUE(contains(typo, "C_t")) << typo;

  for (const char* malformed : {"viscosity", "effects.stokes_head", "", "medium"}) {
    SCOPED_TRACE(malformed);
    configErrorOf([&] { sim_.setParameter(malformed, 1.0); });
    configErrorOf([&] { sim_.parameter(malformed); });
  }
  configErrorOf([&] { sim_.parameter("medium.bogus"); });
}

TEST_F(SimulationParameters, OutOfRangeIsRejectedAndNeverClamped) {
  struct Bad {
    const char* name;
    double value;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Bad> cases{
      {"effects.stokes_head.C_t", -1.0},
      {"effects.stokes_head.C_t", kHeadDragMax * (1.0 + 1e-12)},
      {"effects.stokes_head.C_t", nan},
      {"effects.stokes_head.C_t", inf},
      {"effects.stokes_head.C_r", -1e-12},
      {"medium.viscosity", -1.0},
      {"medium.viscosity", nan},
      {"medium.viscosity", -inf},
  };
  for (const Bad& bad : cases) {
    SCOPED_TRACE(std::string(bad.name) + " = " + std::to_string(bad.value));
    const double before = sim_.parameter(bad.name);
    const std::string msg = configErrorOf([&] { sim_.setParameter(bad.name, bad.value); });
    EXPECT_TRUE(namesFieldAndRange(msg, bad.name)) << msg;
    EXPECT_EQ(sim_.parameter(bad.name), before) << "value changed after a rejected set";
  }
}

// ---------------------------------------------------------------------------------------------
// interface_lateral_force, mode integrated
// ---------------------------------------------------------------------------------------------

std::string interfaceConfig(const std::string& lateral_block) {
  return "robot:\n"
         "  n_tails: 3\n"
         "  tail_length: 0.11\n"
         "  tail_edge_length: 4.0e-3\n"
         "  head_radius: 0.016\n"
         "  head_length: 0.06\n"
         "medium:\n"
         "  viscosity: 1.49\n"
         "  up: [0, 1, 0]\n"
         "effects:\n"
         "  rft:\n"
         "    log_form: \"L/r0\"\n"
         "  stokes_head:\n"
         "    C_t: 4.0\n"
         "    C_r: 2.06\n"
         "  interface_lateral_force:\n" +
         lateral_block +
         "motor:\n"
         "  omega_rpm: 43.27\n";
}

TEST(InterfaceLateralForce, IntegratedModeGivesPositiveCoefficientForDefaultProfile) {
  const TempDir dir;
  const std::string path = dir.write("c.yaml", interfaceConfig("    mode: integrated\n"));
  const Simulation sim(loadSimulationConfig(path));
  const double c_yr = sim.parameter("effects.interface_lateral_force.C_yr");
  EXPECT_GT(c_yr, 0.0);
  EXPECT_TRUE(std::isfinite(c_yr));
  EXPECT_NEAR(c_yr, integratedLateralCoefficient(kDefaultOnsetOverRadius, kDefaultSharpness),
              kExactTol * std::abs(c_yr));
}

TEST(InterfaceLateralForce, FittedModeUsesTheGivenCoefficient) {
  const Simulation sim(loadSimulationConfig(shippedConfig(kInterfaceRobot)));
  EXPECT_DOUBLE_EQ(sim.parameter("effects.interface_lateral_force.C_yr"), 6.0);
}

TEST(InterfaceLateralForce, CoefficientGivenInIntegratedModeIsRejected) {
  const TempDir dir;
  const std::string path =
      dir.write("c.yaml", interfaceConfig("    mode: integrated\n    C_yr: 2.0\n"));
  const std::string msg = loadError(path);
  EXPECT_TRUE(contains(msg, "effects.interface_lateral_force.C_yr")) << msg;
  EXPECT_TRUE(contains(msg, "integrated")) << msg;
}

TEST(InterfaceLateralForce, UnknownModeListsTheModes) {
  const TempDir dir;
  const std::string path = dir.write("c.yaml", interfaceConfig("    mode: guessed\n"));
  const std::string msg = loadError(path);
  EXPECT_TRUE(contains(msg, "effects.interface_lateral_force.mode")) << msg;
  EXPECT_TRUE(contains(msg, "fitted")) << msg;
  EXPECT_TRUE(contains(msg, "integrated")) << msg;
}

}  // namespace
}  // namespace flagella
