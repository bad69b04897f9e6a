// Everything a run needs, loaded from one YAML file (see config/*.yaml and README "Config").
#pragma once

#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "flagella_sim/actuation/slider.h"
#include "flagella_sim/effects/effect_descriptor.h"
#include "flagella_sim/effects/medium.h"
#include "flagella_sim/effects/rft_coefficients.h"
#include "flagella_sim/robots/helical_robot.h"
#include "flagella_sim/robots/multi_tail_robot.h"
#include "flagella_sim/robots/robot_registry.h"
#include "flagella_sim/solver/newton_options.h"

namespace flagella {

struct MotorSpec {
  std::string mode = "constant";   ///< constant | binary
  double omega = 0.0;              ///< omega_T [rad/s] (config gives rpm)
  double positive_duration = 1.0;  ///< binary: time at +omega [s]
  double negative_duration = 1.0;  ///< binary: time at -omega [s]
  double ramp_time = 0.0;          ///< soft start [s]
};

struct SimulationConfig {
  std::string source = "<inline>";  ///< file name, for messages
  /// Section robot: its type (robot.type, robot_registry.h) with its geometry.
  std::shared_ptr<const RobotModel> robot = defaultRobot();
  double head_radius = 0.02;  ///< a (or R): head drag radius [m] (helical: R_H)
  double head_length = 0.04;  ///< L_head [m] (helical: 4 R_H / 3, the sphere's volume)
  Medium medium;
  std::vector<EffectSpec> effects;
  MotorSpec motor;
  SliderSpec slider;  ///< section `slider:` (mass-transformer, docs/model.md 5); needs com_offset
  double dt = 0.01;
  double duration = 10.0;
  double output_interval = 0.1;
  double steady_fraction = 0.5;  ///< last fraction of the run used for summary metrics
  /// Flagellum tilt above which a run counts as buckled [deg] (docs/model.md 8.4.4).
  double buckling_tilt_deg = 15.0;
  NewtonOptions solver;
  /// solver.size_check: refuse configs whose dense blocks this machine cannot hold or step in
  /// reasonable time (simulation/problem_size.h).
  bool size_check = true;

  /// robot.type (multi_tail, helical, ...).
  const std::string& robotType() const { return robot->type(); }
  /// The robot's geometry if its type has geometry G (MultiTailGeometry, HelicalGeometry), else
  /// nullptr.
  template <class G>
  const G* findRobotGeometry() const {
    const auto* typed = dynamic_cast<const RobotModelOf<G>*>(robot.get());
    return typed ? &typed->geometry : nullptr;
  }
  /// The same; std::logic_error naming the robot's type if it has another geometry.
  template <class G>
  const G& robotGeometry() const {
    if (const G* g = findRobotGeometry<G>()) return *g;
    throw std::logic_error("the config's robot (robot.type " + robotType() +
                           ") has another geometry");
  }
  /// The geometry to edit (tests, tools): this config's own copy of the robot (copy-on-write).
  template <class G>
  G& editRobotGeometry() {
    robotGeometry<G>();  // the type check
    std::shared_ptr<RobotModel> copy = robot->clone();
    G& g = static_cast<RobotModelOf<G>&>(*copy).geometry;
    robot = std::move(copy);
    return g;
  }
  /// The configured effect of this registry name (e.g. ComOffset::kName), or nullptr.
  const EffectSpec* effect(const std::string& name) const {
    for (const EffectSpec& e : effects)
      if (e.name == name) return &e;
    return nullptr;
  }
  /// The robot's sizes effects take their defaults from.
  RobotDimensions robotDimensions() const;
};

/// Parses and validates a config tree, effects included (every effect is built once with its
/// parameters); throws ConfigError naming the field and its allowed range. The one path from
/// YAML to a SimulationConfig: the CLI, the nodes and identification all come through here.
SimulationConfig parseSimulationConfig(const YAML::Node& root, const std::string& source);

/// Reads a YAML config file and applies "section.field=value" overrides, without parsing it
/// (identification edits the tree). Errors name the file, line and column.
YAML::Node loadConfigTree(const std::string& path, const std::vector<std::string>& overrides = {});

/// loadConfigTree, then parseSimulationConfig; every error message starts with the file name.
SimulationConfig loadSimulationConfig(const std::string& path,
                                      const std::vector<std::string>& overrides = {});

}  // namespace flagella
