// The robot registry (robot_registry.h): the shipped types in list order, a third type registered
// from the test tree that configs, the simulation and the tables take without any library change,
// each type's recorded schema against its parser, bad input, and the README's robot tables.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/single_tail_robot.h"

namespace flagella {
namespace {

using testing::SingleTailGeometry;

constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;

YAML::Node design1WithRobot(const YAML::Node& robot) {
  YAML::Node root = loadConfigTree(std::string(kConfigDir) + "/granular_design1.yaml");
  root["robot"] = robot;
  return root;
}

YAML::Node singleTailSection() {
  YAML::Node robot;
  robot["type"] = "test_single_tail";
  robot["tail_length"] = 0.04;
  robot["tail_edges"] = 8;
  robot["head_radius"] = 0.012;
  return robot;
}

class RobotRegistry : public ::testing::Test {
 protected:
  void SetUp() override { testing::registerSingleTailRobot(); }
};

TEST_F(RobotRegistry, ShippedTypesFirstInListOrderThenRegistered) {
  const std::vector<std::string> names = registeredRobotNames();
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], "multi_tail");
  EXPECT_EQ(names[1], "helical");
  EXPECT_EQ(names[2], "test_single_tail");
  ASSERT_EQ(listedRobotTypes().size(), 2u);  // the registered one is not shipped
  EXPECT_EQ(defaultRobot()->type(), "multi_tail");
  EXPECT_EQ(SimulationConfig().robotType(), "multi_tail");
}

TEST_F(RobotRegistry, RegisteredTypeRunsThroughConfigAndSimulation) {
  const SimulationConfig c = parseSimulationConfig(design1WithRobot(singleTailSection()), "test");
  EXPECT_EQ(c.robotType(), "test_single_tail");
  const SingleTailGeometry* g = c.findRobotGeometry<SingleTailGeometry>();
  ASSERT_NE(g, nullptr);
  EXPECT_DOUBLE_EQ(g->tail_length, 0.04);
  EXPECT_EQ(g->tail_edges, 8);
  EXPECT_EQ(c.findRobotGeometry<MultiTailGeometry>(), nullptr);
  EXPECT_THROW(c.robotGeometry<HelicalGeometry>(), std::logic_error);
  // The head's sizes and the convergence scales come from the type (docs/model.md 1.10).
  EXPECT_DOUBLE_EQ(c.head_radius, 0.012);
  EXPECT_DOUBLE_EQ(c.head_length, 0.024);
  const double EI = g->material.EI();
  EXPECT_DOUBLE_EQ(c.solver.force_scale, EI / (0.04 * 0.04));
  EXPECT_DOUBLE_EQ(c.solver.moment_scale, EI / 0.04);

  Simulation sim(c);
  // 3 head/shaft nodes, one spoke tip, 8 tail edges: the network the type's builder makes.
  EXPECT_EQ(sim.network().numNodes(), c.robot->build().numNodes());
  EXPECT_EQ(sim.network().parts.tail_nodes.size(), 1u);
  EXPECT_EQ(sim.network().parts.tail_nodes.front().size(), 9u);
  for (int k = 0; k < 30; ++k) sim.step();
  EXPECT_GT(sim.state().time, 0.29);
  EXPECT_TRUE(sim.state().q.allFinite());
  EXPECT_FALSE(c.robot->hasFlagellumTilt());
  EXPECT_EQ(sim.trajectory().back().flagellum_tilt, 0.0);  // no helix: no tilt recorded

  const std::vector<SummaryField> fields = c.robot->summaryFields();
  ASSERT_EQ(fields.size(), 2u);
  EXPECT_EQ(std::get<std::string>(fields[0].value), "test_single_tail");
  EXPECT_DOUBLE_EQ(std::get<double>(fields[1].value), 0.04);
  EXPECT_EQ(c.robot->tailCount(), 1);
}

TEST_F(RobotRegistry, BadInputNamesTheFieldAndEveryType) {
  YAML::Node robot = singleTailSection();
  robot["tail_edges"] = 1;
  try {
    parseSimulationConfig(design1WithRobot(robot), "test");
    FAIL() << "tail_edges 1 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("robot.tail_edges"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[2, 200]"), std::string::npos) << e.what();
  }
  robot = singleTailSection();
  robot["n_tails"] = 2;  // a multi-tail field: unknown to this type
  try {
    parseSimulationConfig(design1WithRobot(robot), "test");
    FAIL() << "robot.n_tails accepted by test_single_tail";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown field 'robot.n_tails'"), std::string::npos)
        << e.what();
  }
  robot["type"] = "bogus";
  try {
    parseSimulationConfig(design1WithRobot(robot), "test");
    FAIL() << "robot.type bogus accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("one of: multi_tail, helical, test_single_tail"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(registerRobotType(testing::singleTailRobotType()), std::invalid_argument);
  RobotDescriptor nameless = testing::singleTailRobotType();
  nameless.name = "";
  EXPECT_THROW(registerRobotType(nameless), std::invalid_argument);
  RobotDescriptor no_parser{"no_parser", "", nullptr};
  EXPECT_THROW(registerRobotType(no_parser), std::invalid_argument);
}

TEST_F(RobotRegistry, EditingACopiedConfigLeavesTheOriginal) {
  const SimulationConfig original =
      loadSimulationConfig(std::string(kConfigDir) + "/granular_design1.yaml");
  SimulationConfig copy = original;
  copy.editRobotGeometry<MultiTailGeometry>().tail_edges = 12;
  EXPECT_EQ(copy.robotGeometry<MultiTailGeometry>().tail_edges, 12);
  EXPECT_EQ(original.robotGeometry<MultiTailGeometry>().tail_edges, 27);
  EXPECT_THROW(copy.editRobotGeometry<HelicalGeometry>(), std::logic_error);
}

// Each field of a type's recorded schema is one its parser takes (given its default, or a value
// in range for a field without one), every shipped config's robot fields are in the schema, and
// each type's defaults equal an empty section's.
TEST_F(RobotRegistry, SchemaIsWhatTheParserReads) {
  for (const RobotDescriptor* type : robotRegistry()) {
    const std::vector<FieldSchema> schema = robotSchema(*type);
    ASSERT_FALSE(schema.empty()) << type->name;
    for (const FieldSchema& f : schema) {
      ASSERT_EQ(f.field.rfind("robot.", 0), 0u) << f.field;
      if (f.fallback.empty()) continue;  // exclusive alternatives and optional lists
      YAML::Node robot;
      robot["type"] = type->name;
      robot[f.field.substr(6)] = YAML::Load(f.fallback);
      FieldReader reader(robot, "robot");
      reader.choice("type", type->name, registeredRobotNames());
      RobotHeadSize head;
      EXPECT_NO_THROW({
        type->parse(reader, head);
        reader.rejectUnknown();
      }) << type->name
         << ": " << f.field << " = " << f.fallback;
    }
  }
  for (const char* file : {"granular_design1", "granular_design2", "interface_robot",
                           "helical_robot", "helical_gimbal", "helical_steering_source"}) {
    const YAML::Node robot =
        loadConfigTree(std::string(kConfigDir) + "/" + file + ".yaml")["robot"];
    const std::string type = robot["type"] ? robot["type"].as<std::string>() : "multi_tail";
    const std::vector<FieldSchema> schema = robotSchema(*findRobotDescriptor(type));
    for (const auto& entry : robot) {
      const std::string key = "robot." + entry.first.as<std::string>();
      if (key == "robot.type") continue;
      bool listed = false;
      for (const FieldSchema& f : schema) listed = listed || f.field == key;
      EXPECT_TRUE(listed) << file << ": " << key << " is not in the " << type << " schema";
    }
  }
}

TEST_F(RobotRegistry, MarkdownListsEveryRegisteredType) {
  const std::string all = robotTableMarkdown(robotRegistry());
  EXPECT_NE(all.find("`robot.type: test_single_tail`"), std::string::npos);
  EXPECT_NE(all.find("| `robot.tail_edges` | 10 | integer in [2, 200] | - |"), std::string::npos)
      << all;
  EXPECT_EQ(robotTableMarkdown(listedRobotTypes()).find("test_single_tail"), std::string::npos);
}

// README "Robots: the registry" holds exactly the shipped types' tables.
TEST_F(RobotRegistry, ReadmeTablesAreTheRegistrysTables) {
  std::ifstream readme(std::string(kConfigDir) + "/../README.md");
  ASSERT_TRUE(readme.good());
  std::stringstream text;
  text << readme.rdbuf();
  const std::string tables = robotTableMarkdown(listedRobotTypes());
  EXPECT_NE(text.str().find(tables), std::string::npos)
      << "README.md is out of date; replace its robot tables with the output of "
         "`flagella_run robots --markdown`:\n"
      << tables;
}

}  // namespace
}  // namespace flagella
