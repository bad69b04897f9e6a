// One headless steering run (flagella_steer, the robustness tool, tests): the core simulator and
// the mass-transformer controller over LCM (memq://, no ROS), the model possibly wrong
// (model errors scale config values the calibration assumed), noisy sensors seeded. Scored on
// the true head path: a waypoint is reached when the path comes within the tolerance.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "flagella_control/command_replay.h"
#include "flagella_control/mass_transformer_controller.h"
#include "flagella_sim/runtime/sim_session.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control {

/// Config overrides "field=value" that scale config values by factors: `errors` holds
/// (key, factor) with key a config field (section.field) or one of the aliases eps
/// (effects.rss.eps_ratio), E (robot.youngs_modulus), C_t, C_r (effects.stokes_head.*) and
/// l_0 (effects.com_offset.offset). The nominal value is the file's (after `overrides`), else
/// the simulation's default. Throws ConfigError naming an unknown key or a bad factor.
std::vector<std::string> modelErrorOverrides(
    const std::string& config_path, const std::vector<std::string>& overrides,
    const std::vector<std::pair<std::string, double>>& errors);

/// The sensors of a steering run (defaults: a noisy ADXL345 feeding the IMU message, IMU
/// orientation noise, two cameras at 1 Hz with 1 mm noise).
flagella::SessionOptions steeringSessionOptions(const flagella::SimulationConfig& config,
                                                const SteeringCalibration& calibration,
                                                unsigned seed);

struct SteeringSample {
  double time = 0.0;
  Vec3 position = Vec3::Zero();            ///< true head centre, output frame
  Vec3 estimate = Vec3::Zero();            ///< the controller's estimate
  Vec3 forward = Vec3::UnitX();            ///< true direction of the head axis -t^0
  Vec3 estimated_forward = Vec3::UnitX();  ///< the controller's direction of travel
  double motor = 0.0, slider = 0.0;        ///< applied motor rate [rad/s], slider position [m]
  double azimuth_error = 0.0, elevation = 0.0, target_elevation = 0.0;  ///< status [rad]
  double crab = 0.0;                         ///< status: course minus axis azimuth [rad]
  double neutral = 0.0, steer_offset = 0.0;  ///< status: slider neutral, offset [m]
  double pitch_neutral = NAN;                ///< status: the neutral the pitch gives [m]
  int waypoint = 0;                          ///< status: the waypoint approached
  SteeringMode mode = SteeringMode::Waiting;
};

struct SteeringRunResult {
  int reached = 0;  ///< waypoints the true path came within the tolerance of
  /// Waypoints reached in the mission's order: the k-th counts only once the path came within the
  /// tolerance of it after reaching the (k-1)-th (a path wandering past waypoints out of turn
  /// scores `reached` but not this).
  int reached_in_order = 0;
  int total = 0;
  double tolerance = 0.0;    ///< the mission's reach tolerance [m]
  std::vector<double> miss;  ///< closest approach of the true path per waypoint [m]
  double max_miss = 0.0;     ///< [m]
  bool finished = false;     ///< the controller declared every waypoint reached
  double time = 0.0;         ///< simulated time at the end [s]
  double wall_seconds = 0.0;
  bool halted = false;
  std::string halt_reason;  ///< the simulator's message when it halted
  /// Time each waypoint was reached in the mission's order [s] (NaN: not so reached).
  std::vector<double> reach_time;
  /// Slider positions the run used: lowest and highest over every step [m] (NaN: no slider).
  double slider_low = NAN, slider_high = NAN;
  /// The simulator's failure strategy at work (README, "Numerical failure"): steps solved only as
  /// subdivided steps, (sub)steps solved only by the damped retry, and steps that failed even so
  /// and were retried with the motor stopped (a run halts only when that fails too).
  long subdivided_steps = 0, damped_steps = 0, motor_stop_retries = 0;
  long cycles = 0;
  /// The controller's slider neutral at the end, and the start frame's pitch trim (NaN when
  /// none; open-loop replays: NaN) [m].
  double neutral = NAN, trim_neutral = NAN;
  bool trimmed = false;
  double pitch_neutral = NAN;  ///< the neutral the mission's pitch gave at the end [m]
  long retrims = 0;            ///< times the neutral was re-trimmed from the pitch
  std::vector<std::pair<double, SteeringMode>> modes;  ///< mode changes (time, new mode)
  std::vector<SteeringSample> samples;
  std::vector<Vec3> waypoints;  ///< in the world
};

/// Runs until the controller finishes or `max_duration` of simulated time. With `recorded`, the
/// controller's commands are kept there (the open-loop schedule of runOpenLoop).
/// `progress`, if set, is called after every step with the simulated time (for progress lines).
SteeringRunResult runSteering(const flagella::SimulationConfig& config,
                              const flagella::SessionOptions& session_options,
                              MassTransformerController& controller, double max_duration,
                              double sample_interval = 0.5,
                              std::vector<RecordedCommand>* recorded = nullptr,
                              const std::function<void(double)>& progress = {});

/// Replays recorded commands open loop (no feedback) and scores the true path against
/// `waypoints` (world) within `tolerance`, until the schedule ends or `max_duration`.
SteeringRunResult runOpenLoop(const flagella::SimulationConfig& config,
                              const flagella::SessionOptions& session_options,
                              const std::vector<RecordedCommand>& commands, double rest_slider,
                              const std::vector<Vec3>& waypoints, double tolerance,
                              double max_duration, double sample_interval = 0.5);

/// A number for JSON: 10 significant digits, null when not finite.
std::string jsonNumber(double x);
/// `text` for a JSON string: quotes and backslashes escaped, newlines and tabs as spaces.
std::string jsonEscaped(const std::string& text);

/// The result as JSON (reached, total, max_miss_mm, time_s, modes, ...).
std::string steeringResultJson(const SteeringRunResult& result, const std::string& controller,
                               const std::string& mission);

/// The sampled path as CSV: time, true and estimated position, motor, slider, mode, then the
/// true head axis and estimated direction of travel and the status angles (the plot's input).
std::string steeringPathCsv(const SteeringRunResult& result);

}  // namespace flagella::control
