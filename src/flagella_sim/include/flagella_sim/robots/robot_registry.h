// The table of every robot type a config can name (robot.type; src/robots/robot_list.def, plus
// types registered at run time, e.g. a test's own robot): config parsing, `flagella_run robots`
// and the README's robot table iterate it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "flagella_sim/core/yaml_fields.h"
#include "flagella_sim/robots/robot_model.h"

namespace flagella {

/// The head's sizes a robot's section sets: a (or R) and L_head [m] (the Stokes drag's and the
/// buoyancy's defaults).
struct RobotHeadSize {
  double radius = 0.02;
  double length = 0.04;
};

struct RobotDescriptor {
  std::string name;         ///< robot.type
  std::string description;  ///< one line: what the robot is, its docs/model.md section
  /// Reads the robot's fields of section `robot` (all but `type`; ranges and cross-field rules
  /// checked, ConfigError naming the field) and sets the head's sizes. Called on an empty
  /// section it gives the defaults, and with FieldReader::recordSchema the schema.
  std::function<std::shared_ptr<RobotModel>(FieldReader& robot, RobotHeadSize& head)> parse;
};

/// Every robot type: the list's, in its order, then the registered ones.
const std::vector<const RobotDescriptor*>& robotRegistry();
/// The types of robot_list.def only (what the product ships), in its order.
std::vector<const RobotDescriptor*> listedRobotTypes();
/// Adds a robot type (kept for the program's life); std::invalid_argument for a taken or empty
/// name or no parse function.
void registerRobotType(const RobotDescriptor& descriptor);
/// The descriptor of `name`, or nullptr.
const RobotDescriptor* findRobotDescriptor(const std::string& name);
/// The registered type names, in order.
std::vector<std::string> registeredRobotNames();
/// Reads a config's section `robot`: robot.type names the type (default: the first registered),
/// whose descriptor reads the other fields and sets `head`; unknown fields are refused
/// (ConfigError naming the field).
std::shared_ptr<RobotModel> parseRobotSection(FieldReader& robot, RobotHeadSize& head);
/// The robot of a config that names none: the list's first type with its defaults.
std::shared_ptr<const RobotModel> defaultRobot();

/// The fields a robot type reads (name, default, range, unit), in its parser's order: its parse
/// run on an empty section with FieldReader::recordSchema.
std::vector<FieldSchema> robotSchema(const RobotDescriptor& type);

/// Each type's fields, one Markdown table per type (README, "Robots: the registry", holds the
/// listed types' tables; `flagella_run robots --markdown` prints every registered type's).
std::string robotTableMarkdown(const std::vector<const RobotDescriptor*>& types);

}  // namespace flagella
