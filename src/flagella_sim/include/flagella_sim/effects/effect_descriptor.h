// What the effect registry knows of one effect: its name, a one-line description, the option
// schema (structural choices and named parameters with units, defaults and ranges), how to build
// it from a config, and, for effects that model discovery may try, what a fit may change. Each
// effect's own file defines its descriptor; effect_list.def names them all.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/effects/effect.h"
#include "flagella_sim/effects/medium.h"

namespace flagella {

/// A structural option: chosen once in the config, never fitted ("log_form", "mode").
struct EffectOption {
  std::string name;
  std::string fallback;              ///< default value ("true"/"false" for a flag)
  std::vector<std::string> allowed;  ///< the choices; empty for a flag
  std::string description;
  bool isFlag() const { return allowed.empty(); }
  /// The values a config may give: "true, false" for a flag, else the choices.
  std::string choiceList() const { return isFlag() ? "true, false" : joined(allowed); }
};

/// The settings of one effect as a config gives them.
struct EffectSpec {
  std::string name;
  /// Structural options by name, every option of the descriptor present (defaults filled in).
  std::vector<std::pair<std::string, std::string>> options;
  std::vector<std::pair<std::string, double>> parameters;  ///< name -> value, in config order

  /// The value of a structural option ("" if the effect has no such option).
  const std::string& option(const std::string& name) const;
  bool flag(const std::string& name) const { return option(name) == "true"; }
  bool hasParameter(const std::string& name) const;
};

/// The robot's sizes that effects take their defaults from.
struct RobotDimensions {
  double head_radius = 0.02;        ///< a (or R) [m]
  double head_length = 0.04;        ///< L_head [m]
  double body_density = 1000.0;     ///< density of the robot's material [kg/m^3]
  double filament_radius = 3.2e-3;  ///< r0 of the tails or the flagellum [m]
};

/// What a descriptor's factory sees: the effect's settings, the medium and the robot's sizes.
struct EffectBuildContext {
  const EffectSpec& spec;
  const Medium& medium;
  const RobotDimensions& robot;
};

/// What kinds of measurement discovery needs before a fit can tell an effect apart.
enum Observable : unsigned {
  kTranslation = 1u << 0,   ///< v, or head positions over time
  kRotation = 1u << 1,      ///< omega_h / omega_t, or counted turns
  kHeading = 1u << 2,       ///< omega_yr / R_yr, or the horizontal path of a time series
  kVertical = 1u << 3,      ///< vertical head position or orientation of a time series
  kTimeResolved = 1u << 4,  ///< a time series (events within a run)
  kSessionTime = 1u << 5,   ///< experiments spread over the session (time_s, session_time_s)
  kTilt = 1u << 6,          ///< the flagellum's tilt against the head axis (tilt_deg)
  kLastObservable = kTilt,
};

/// One variable a discovery fit changes: an effect parameter, or its reciprocal.
struct FittableParameter {
  std::string variable;     ///< name in fits and reports ("stall_torque", "inverse_stall_torque")
  std::string parameter;    ///< the effect parameter it sets
  bool reciprocal = false;  ///< parameter = 1 / variable
  std::string unit;         ///< of the variable
  double lower = 0.0, upper = 0.0;  ///< fit range of the variable (inside the parameter's range)
  bool log_scale = false;           ///< fitted as log(variable): positive, spans decades
  /// The value inside [lower, upper] at which the effect vanishes, or is weakest where the range
  /// excludes "none" (a log-scale variable): a nested fit starts from the simpler model's
  /// optimum with the effect here, so it can only improve on that model (README, discovery).
  double off = 0.0;
};

/// A realistic strength for generated test data: drawn log-uniformly in [low, high].
struct TypicalStrength {
  std::string variable;
  double low = 0.0, high = 0.0;
  bool random_sign = false;
};

/// How model discovery may try an effect as the cause of a discrepancy.
struct DiscoveryHints {
  std::string title;      ///< e.g. "granular yield threshold"
  std::string signature;  ///< what it does to data, in the words of the diagnosis
  unsigned needs = 0;     ///< Observable bits that must all be present
  std::vector<FittableParameter> variables;
  /// Start points (one value per variable) tried before the joint fit; the best one starts it.
  std::vector<std::vector<double>> starts;
  /// Parameter set to the experiment's session start time (empty: none).
  std::string session_time_parameter;
  /// Strengths the hidden-effect test data draw, in this order.
  std::vector<TypicalStrength> typical;
  /// The same on a single-flagellum swimmer, where they differ (empty: `typical`): its head
  /// spins slowly, and its whole body pitches under a small gravity couple.
  std::vector<TypicalStrength> typical_single_flagellum;
  bool steady_table_data =
      true;  ///< its hidden-effect case is a steady-state table (else a series)
  /// An effect the robot's config must have for this one to act ("": none), and what that
  /// effect stands for: granular yield and jamming act only in a granular medium, which this
  /// project models by resistive force theory ("rft"); a swimmer in a liquid modelled by
  /// Stokeslets has none, and discovery does not try them there.
  std::string requires_effect;
  std::string requires_what;
};

struct EffectDescriptor {
  std::string name;
  std::string description;  ///< one line
  std::vector<EffectOption> options;
  /// Named parameters: default value, range, unit, description. A default that depends on
  /// the robot or medium is set by `make`; `default_rule` then says how (README, `params`).
  std::vector<ParameterSpec> parameters;
  std::vector<std::pair<std::string, std::string>> default_rules;  ///< parameter -> rule
  /// Pairs of parameters that say the same thing two ways (eps, eps_ratio): a config gives at
  /// most one of each pair (makeEffect rejects both).
  std::vector<std::pair<std::string, std::string>> exclusive_parameters;
  std::function<EffectPtr(const EffectBuildContext&)> make;
  std::optional<DiscoveryHints> discovery;

  const ParameterSpec& parameter(const std::string& name) const;
  const EffectOption* findOption(const std::string& name) const;
  /// "" unless a rule gives this parameter's default.
  std::string defaultRule(const std::string& parameter) const;
};

}  // namespace flagella
