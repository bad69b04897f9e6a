#include "flagella_sim/robots/robot_registry.h"

#include <stdexcept>

#include "flagella_sim/core/text_lists.h"

// The descriptor functions, declared from the list itself so that a robot type is one line there.
#define FLAGELLA_ROBOT(descriptor)     \
  namespace flagella {                 \
  const RobotDescriptor& descriptor(); \
  }
#include "robot_list.def"
#undef FLAGELLA_ROBOT

namespace flagella {

namespace {

std::vector<const RobotDescriptor*>& mutableRegistry() {
  static std::vector<const RobotDescriptor*> table = listedRobotTypes();
  return table;
}

// The type parsed from an empty section: its defaults, and (with `schema`) the fields it reads.
std::shared_ptr<RobotModel> parseEmptySection(const RobotDescriptor& type,
                                              std::vector<FieldSchema>* schema) {
  FieldReader empty(YAML::Node(), "robot");
  empty.recordSchema(schema);
  RobotHeadSize head;
  return type.parse(empty, head);
}

}  // namespace

const std::vector<const RobotDescriptor*>& robotRegistry() { return mutableRegistry(); }

std::vector<const RobotDescriptor*> listedRobotTypes() {
  return {
#define FLAGELLA_ROBOT(descriptor) &descriptor(),
#include "robot_list.def"
#undef FLAGELLA_ROBOT
  };
}

void registerRobotType(const RobotDescriptor& descriptor) {
  if (descriptor.name.empty() || !descriptor.parse)
    throw std::invalid_argument(
        "registerRobotType: a robot type needs a name and a parse function");
  if (findRobotDescriptor(descriptor.name))
    throw std::invalid_argument("registerRobotType: robot type '" + descriptor.name +
                                "' is already registered");
  mutableRegistry().push_back(new RobotDescriptor(descriptor));  // kept for the program's life
}

const RobotDescriptor* findRobotDescriptor(const std::string& name) {
  for (const RobotDescriptor* d : robotRegistry())
    if (d->name == name) return d;
  return nullptr;
}

std::vector<std::string> registeredRobotNames() {
  std::vector<std::string> names;
  for (const RobotDescriptor* d : robotRegistry()) names.push_back(d->name);
  return names;
}

std::shared_ptr<RobotModel> parseRobotSection(FieldReader& robot, RobotHeadSize& head) {
  const std::vector<std::string> types = registeredRobotNames();
  const RobotDescriptor* d = findRobotDescriptor(robot.choice("type", types.front(), types));
  std::shared_ptr<RobotModel> model = d->parse(robot, head);
  robot.rejectUnknown();
  return model;
}

std::shared_ptr<const RobotModel> defaultRobot() {
  static const std::shared_ptr<const RobotModel> robot =
      parseEmptySection(*robotRegistry().front(), nullptr);
  return robot;
}

namespace {

std::string cell(const std::string& text) { return text.empty() ? "-" : text; }

}  // namespace

std::vector<FieldSchema> robotSchema(const RobotDescriptor& type) {
  std::vector<FieldSchema> fields;
  parseEmptySection(type, &fields);
  return fields;
}

std::string robotTableMarkdown(const std::vector<const RobotDescriptor*>& types) {
  std::string out;
  for (const RobotDescriptor* d : types) {
    const std::vector<FieldSchema> fields = robotSchema(*d);
    out += "`robot.type: " + d->name + "`: " + d->description + "\n\n";
    out += "| field | default | allowed | unit |\n|---|---|---|---|\n";
    for (const FieldSchema& f : fields)
      out += "| `" + f.field + "` | " + cell(f.fallback) + " | " + f.range + " | " + cell(f.unit) +
             " |\n";
    out += "\n";
  }
  return out;
}

}  // namespace flagella
