// Everything a run needs, loaded from one YAML file (see config/*.yaml and README "Config").
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "flagella_sim/effects/medium.h"
#include "flagella_sim/effects/rft_coefficients.h"
#include "flagella_sim/robots/multi_tail_robot.h"
#include "flagella_sim/solver/newton_options.h"

namespace flagella {

struct MotorSpec {
  std::string mode = "constant";   ///< constant | binary
  double omega = 0.0;              ///< omega_T [rad/s] (config gives rpm)
  double positive_duration = 1.0;  ///< binary: time at +omega [s]
  double negative_duration = 1.0;  ///< binary: time at -omega [s]
  double ramp_time = 0.0;          ///< soft start [s]
};

/// One external effect switched on by name, with its options and parameter values.
struct EffectSpec {
  std::string name;
  std::string log_form = "2L/r0";       ///< rft
  bool use_interface_profile = false;   ///< rft
  std::string lateral_mode = "fitted";  ///< interface_lateral_force: fitted | integrated
  std::vector<std::pair<std::string, double>> parameters;  ///< name -> value overrides
};

struct SimulationConfig {
  std::string source = "<inline>";  ///< file name, for messages
  std::string robot_name;
  MultiTailGeometry geometry;
  double head_radius = 0.02;  ///< a (or R): head drag radius [m]
  double head_length = 0.04;  ///< L_head [m]
  Medium medium;
  std::vector<EffectSpec> effects;
  MotorSpec motor;
  double dt = 0.01;
  double duration = 10.0;
  double output_interval = 0.1;
  double steady_fraction = 0.5;  ///< last fraction of the run used for summary metrics
  NewtonOptions solver;
};

/// Parses a config tree; throws ConfigError naming the field and its allowed range.
SimulationConfig parseSimulationConfig(const YAML::Node& root, const std::string& source);

/// Loads a YAML file, applies "section.field=value" overrides, parses. File/line errors included.
SimulationConfig loadSimulationConfig(const std::string& path,
                                      const std::vector<std::string>& overrides = {});

/// The names of the effects a config may switch on.
const std::vector<std::string>& knownEffectNames();

}  // namespace flagella
