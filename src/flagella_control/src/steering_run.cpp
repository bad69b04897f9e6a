#include "flagella_control/steering_run.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include "flagella_control/lcm_harness.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella::control {

namespace {

const std::map<std::string, std::string>& aliases() {
  static const std::map<std::string, std::string> a = {{"eps", "effects.rss.eps_ratio"},
                                                       {"E", "robot.youngs_modulus"},
                                                       {"C_t", "effects.stokes_head.C_t"},
                                                       {"C_r", "effects.stokes_head.C_r"},
                                                       {"l_0", "effects.com_offset.offset"},
                                                       {"m_s", "slider.mass"},
                                                       // stall torque = k_t V / R at a fixed
                                                       // supply: scales with k_t
                                                       {"k_t", "effects.dc_motor.stall_torque"}};
  return a;
}

// The value at a dotted path of the YAML file, after "field=value" overrides of the same path.
bool fileValue(const YAML::Node& root, const std::string& field,
               const std::vector<std::string>& overrides, double& value) {
  for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
    if (it->rfind(field + "=", 0) == 0) {
      value = std::stod(it->substr(field.size() + 1));
      return true;
    }
  }
  YAML::Node node = YAML::Clone(root);
  std::stringstream path(field);
  std::string part;
  while (std::getline(path, part, '.')) {
    if (!node.IsMap() || !node[part]) return false;
    node = node[part];
  }
  if (!node.IsScalar()) return false;
  value = node.as<double>();
  return true;
}

}  // namespace

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

std::string jsonEscaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += (c == '\n' || c == '\t') ? ' ' : c;
  }
  return out;
}

std::vector<std::string> modelErrorOverrides(
    const std::string& config_path, const std::vector<std::string>& overrides,
    const std::vector<std::pair<std::string, double>>& errors) {
  std::vector<std::string> out = overrides;
  if (errors.empty()) return out;
  const YAML::Node root = loadStrictYamlFile(config_path, "config");
  for (const auto& [key, factor] : errors) {
    const auto alias = aliases().find(key);
    const std::string field = alias != aliases().end() ? alias->second : key;
    if (!(factor > 0.0) || !std::isfinite(factor) || factor > 100.0)
      throw flagella::ConfigError("model error " + key + ": factor must be in (0, 100], got " +
                                  std::to_string(factor));
    double nominal = 0.0;
    if (!fileValue(root, field, out, nominal)) {
      try {  // a default of the simulation (e.g. eps_ratio)
        const flagella::Simulation sim(flagella::loadSimulationConfig(config_path, out));
        nominal = sim.parameter(field);
      } catch (const std::exception&) {
        throw flagella::ConfigError(
            "model error '" + key +
            "': not a value of the config (use eps, E, C_t, C_r, l_0, m_s, k_t or a "
            "section.field path; k_t needs effects.dc_motor in the config or a --set of "
            "effects.dc_motor.stall_torque)");
      }
    }
    std::ostringstream entry;
    entry.precision(17);
    entry << field << "=" << nominal * factor;
    out.push_back(entry.str());
  }
  return out;
}

flagella::SessionOptions steeringSessionOptions(const flagella::SimulationConfig& config,
                                                const SteeringCalibration& calibration,
                                                unsigned seed) {
  flagella::SessionOptions o;
  o.initial_motor = "stopped";
  o.max_motor_speed =
      std::max(o.max_motor_speed,
               1.2 * std::max(calibration.relax.pulse_omega, calibration.three_level.pulse_omega));
  if (config.slider.enabled) {
    o.slider_min = config.slider.travel_min;
    o.slider_max = config.slider.travel_max;
  }
  o.imu.orientation_noise_std = 0.005;  // [rad], about 0.3 deg
  o.imu.gyro_noise_std = 0.002;         // [rad/s]
  o.imu.seed = seed;
  o.accelerometer.feeds_imu = true;
  o.accelerometer.seed = seed + 1;
  o.camera.rate = 1.0;
  o.camera.stereo = true;
  o.camera.noise_std = 1e-3;
  o.camera.height_noise_std = 1e-3;
  o.camera.seed = seed + 2;
  return o;
}

namespace {

// What a scored run needs to know of the controller it drives.
struct RunView {
  std::function<SteeringMode()> mode;
  std::function<void(SteeringSample&)> annotate;  // the controller's estimates
  std::function<long()> cycles;
  std::function<void(double)> progress;  // simulated time after each step
};

// Widens the result's slider range [slider_low, slider_high] to the slider's position now.
void trackSliderRange(const flagella::SimSession& session, SteeringRunResult& result) {
  if (const flagella::Slider* slider = session.simulation().slider()) {
    const double x = slider->state().position;
    result.slider_low = std::isnan(result.slider_low) ? x : std::min(result.slider_low, x);
    result.slider_high = std::isnan(result.slider_high) ? x : std::max(result.slider_high, x);
  }
}

// Updates each waypoint's closest approach and the next one's reach time from the head position.
void scoreWaypoints(const Vec3& head_position, double time, double tolerance,
                    std::vector<double>& miss, SteeringRunResult& result) {
  const auto next = static_cast<std::size_t>(result.reached_in_order);
  for (std::size_t i = 0; i < miss.size(); ++i) {
    const double distance = (head_position - result.waypoints[i]).norm();
    miss[i] = std::min(miss[i], distance);
    if (i == next && distance <= tolerance) {
      result.reach_time[i] = time;
      ++result.reached_in_order;
    }
  }
}

// The recorded sample of the session now (the controller's estimates unless waiting).
SteeringSample sampleOf(const flagella::SimSession& session, const flagella::RodSnapshot& s,
                        SteeringMode mode, bool waiting, const RunView& view) {
  SteeringSample sample;
  sample.time = session.time();
  sample.position = s.head_position;
  sample.estimate = s.head_position;
  sample.forward = -(s.head_orientation * Vec3::UnitZ());
  sample.estimated_forward = sample.forward;
  if (view.annotate && !waiting) view.annotate(sample);
  sample.motor = session.health().motor_applied;
  sample.slider = session.health().slider_position;
  sample.mode = mode;
  return sample;
}

// Fills the result's totals from the misses, the harness report and the session's health.
void finishResult(const flagella::SimSession& session, const HarnessReport& report,
                  const std::vector<double>& miss, double tolerance, SteeringMode last_mode,
                  const RunView& view, SteeringRunResult& result) {
  result.total = static_cast<int>(miss.size());
  result.tolerance = tolerance;
  result.miss = miss;
  for (double m : miss) {
    result.max_miss = std::max(result.max_miss, m);
    if (m <= tolerance) ++result.reached;
  }
  result.finished = last_mode == SteeringMode::Finished;
  result.time = report.sim_time;
  result.wall_seconds = report.wall_seconds;
  result.halted = report.halted;
  const flagella::SessionHealth health = session.health();
  if (report.halted) result.halt_reason = health.message;
  result.subdivided_steps = health.subdivided_steps;
  result.damped_steps = health.damped_steps;
  result.motor_stop_retries = health.solver_failures;
  result.cycles = view.cycles ? view.cycles() : 0;
}

// Steps the session with `core` until it finishes or faults, scoring the true head path against
// the waypoints (placed once `mode` leaves Waiting; `waypoints_of` reads them then, and its
// size before is the mission's). A waypoint never placed counts as missed (miss infinite).
SteeringRunResult runScored(const flagella::SimulationConfig& config,
                            const flagella::SessionOptions& session_options, ControllerCore& core,
                            const std::function<std::vector<Vec3>()>& waypoints_of,
                            double tolerance, double max_duration, double sample_interval,
                            const RunView& view) {
  flagella::SimSession session(config, session_options);
  LcmHarness harness(session, core, HarnessOptions{});
  SteeringRunResult result;
  double next_sample = 0.0;
  std::vector<double> miss(waypoints_of().size(), std::numeric_limits<double>::infinity());
  result.reach_time.assign(miss.size(), NAN);
  bool placed = false;
  SteeringMode last_mode = SteeringMode::Waiting;
  const auto after_step = [&]() {
    if (view.progress) view.progress(session.time());
    trackSliderRange(session, result);
    const SteeringMode mode = view.mode();
    if (mode != last_mode) {
      result.modes.emplace_back(session.time(), mode);
      last_mode = mode;
    }
    // While Waiting (the start frame's course being measured) the path is sampled, not scored.
    const bool waiting = mode == SteeringMode::Waiting;
    const bool sample_due = session.time() + 1e-9 >= next_sample;
    if (waiting && !sample_due) return;
    const flagella::RodSnapshot s = session.snapshot();
    if (!waiting) {
      if (!placed) {
        result.waypoints = waypoints_of();
        placed = true;
      }
      scoreWaypoints(s.head_position, session.time(), tolerance, miss, result);
    }
    if (sample_due) {
      next_sample += sample_interval;
      result.samples.push_back(sampleOf(session, s, mode, waiting, view));
    }
    if (mode == SteeringMode::Finished || mode == SteeringMode::Fault) harness.requestStop();
  };
  const HarnessReport report = harness.run(max_duration, after_step);
  finishResult(session, report, miss, tolerance, last_mode, view, result);
  return result;
}

}  // namespace

SteeringRunResult runSteering(const flagella::SimulationConfig& config,
                              const flagella::SessionOptions& session_options,
                              MassTransformerController& controller, double max_duration,
                              double sample_interval, std::vector<RecordedCommand>* recorded,
                              const std::function<void(double)>& progress) {
  RunView view;
  view.progress = progress;
  view.mode = [&]() { return controller.status().mode; };
  view.cycles = [&]() { return controller.status().cycles; };
  view.annotate = [&](SteeringSample& sample) {
    const SteeringStatus& status = controller.status();
    sample.estimate = controller.estimatedPosition();
    sample.estimated_forward = controller.estimatedDirection();
    sample.azimuth_error = status.azimuth_error;
    sample.elevation = status.elevation;
    sample.target_elevation = status.target_elevation;
    sample.crab = status.crab;
    sample.neutral = status.neutral;
    sample.steer_offset = status.steer_offset;
    sample.pitch_neutral = status.pitch_neutral;
    sample.waypoint = status.waypoint;
  };
  const auto waypoints = [&]() { return controller.waypoints(); };
  const double tolerance = controller.mission().tolerance;
  SteeringRunResult result;
  if (!recorded) {
    result = runScored(config, session_options, controller, waypoints, tolerance, max_duration,
                       sample_interval, view);
  } else {
    const double rate = session_options.imu.rate > 0.0 ? session_options.imu.rate : 100.0;
    CommandRecorder recorder(controller, static_cast<std::size_t>(max_duration * rate) + 16);
    result = runScored(config, session_options, recorder, waypoints, tolerance, max_duration,
                       sample_interval, view);
    *recorded = recorder.commands();
  }
  const SteeringStatus& status = controller.status();
  result.neutral = status.neutral;
  result.trim_neutral = status.trim_neutral;
  result.trimmed = status.trimmed;
  result.pitch_neutral = status.pitch_neutral;
  result.retrims = status.retrims;
  return result;
}

SteeringRunResult runOpenLoop(const flagella::SimulationConfig& config,
                              const flagella::SessionOptions& session_options,
                              const std::vector<RecordedCommand>& commands, double rest_slider,
                              const std::vector<Vec3>& waypoints, double tolerance,
                              double max_duration, double sample_interval) {
  CommandReplayController replay(commands, rest_slider);
  RunView view;
  view.mode = [&]() { return replay.finished() ? SteeringMode::Finished : SteeringMode::Cruise; };
  return runScored(
      config, session_options, replay, [&]() { return waypoints; }, tolerance, max_duration,
      sample_interval, view);
}

std::string steeringResultJson(const SteeringRunResult& r, const std::string& controller,
                               const std::string& mission) {
  std::ostringstream j;
  j << "{\n  \"controller\": \"" << controller << "\",\n  \"mission\": \"" << mission << "\",\n";
  j << "  \"reached\": " << r.reached << ",\n  \"reached_in_order\": " << r.reached_in_order
    << ",\n  \"total\": " << r.total << ",\n";
  j << "  \"tolerance_mm\": " << jsonNumber(r.tolerance * 1e3) << ",\n";
  j << "  \"max_miss_mm\": " << jsonNumber(r.max_miss * 1e3) << ",\n";
  j << "  \"miss_mm\": [";
  for (std::size_t i = 0; i < r.miss.size(); ++i)
    j << (i ? ", " : "") << jsonNumber(r.miss[i] * 1e3);
  j << "],\n  \"finished\": " << (r.finished ? "true" : "false") << ",\n";
  j << "  \"reach_time_s\": [";
  for (std::size_t i = 0; i < r.reach_time.size(); ++i)
    j << (i ? ", " : "") << jsonNumber(r.reach_time[i]);
  j << "],\n  \"slider_low_m\": " << jsonNumber(r.slider_low)
    << ",\n  \"slider_high_m\": " << jsonNumber(r.slider_high) << ",\n";
  j << "  \"halted\": " << (r.halted ? "true" : "false") << ",\n";
  if (r.halted) j << "  \"halt_reason\": \"" << jsonEscaped(r.halt_reason) << "\",\n";
  j << "  \"subdivided_steps\": " << r.subdivided_steps
    << ",\n  \"damped_steps\": " << r.damped_steps
    << ",\n  \"motor_stop_retries\": " << r.motor_stop_retries << ",\n";
  j << "  \"time_s\": " << jsonNumber(r.time) << ",\n  \"wall_s\": " << jsonNumber(r.wall_seconds)
    << ",\n  \"buckle_cycles\": " << r.cycles << ",\n  \"neutral_m\": " << jsonNumber(r.neutral)
    << ",\n  \"trim_neutral_m\": " << jsonNumber(r.trim_neutral)
    << ",\n  \"trimmed\": " << (r.trimmed ? "true" : "false")
    << ",\n  \"pitch_neutral_m\": " << jsonNumber(r.pitch_neutral)
    << ",\n  \"retrims\": " << r.retrims << ",\n  \"modes\": [";
  for (std::size_t i = 0; i < r.modes.size(); ++i)
    j << (i ? ", " : "") << "{\"t\": " << jsonNumber(r.modes[i].first) << ", \"mode\": \""
      << steeringModeName(r.modes[i].second) << "\"}";
  j << "],\n  \"waypoints_m\": [";
  for (std::size_t i = 0; i < r.waypoints.size(); ++i)
    j << (i ? ", " : "") << "[" << jsonNumber(r.waypoints[i].x()) << ", "
      << jsonNumber(r.waypoints[i].y()) << ", " << jsonNumber(r.waypoints[i].z()) << "]";
  j << "]\n}\n";
  return j.str();
}

std::string steeringPathCsv(const SteeringRunResult& result) {
  std::ostringstream csv;
  csv.precision(8);
  csv << "time,x,y,z,est_x,est_y,est_z,motor,slider,mode,fx,fy,fz,est_fx,est_fy,est_fz,"
         "azimuth_error,elevation,target_elevation,crab,neutral,steer_offset,waypoint,pitch_"
         "neutral\n";
  for (const SteeringSample& s : result.samples) {
    csv << s.time << "," << s.position.x() << "," << s.position.y() << "," << s.position.z() << ","
        << s.estimate.x() << "," << s.estimate.y() << "," << s.estimate.z() << "," << s.motor << ","
        << s.slider << "," << steeringModeName(s.mode);
    for (const Vec3* v : {&s.forward, &s.estimated_forward})
      csv << "," << v->x() << "," << v->y() << "," << v->z();
    csv << "," << s.azimuth_error << "," << s.elevation << "," << s.target_elevation << ","
        << s.crab << "," << s.neutral << "," << s.steer_offset << "," << s.waypoint << ","
        << s.pitch_neutral << "\n";
  }
  return csv.str();
}

}  // namespace flagella::control
