#include "flagella_control/steering_run.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "flagella_control/lcm_harness.h"
#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella::control {

namespace {

const std::map<std::string, std::string>& aliases() {
  static const std::map<std::string, std::string> a = {{"eps", "effects.rss.eps_ratio"},
                                                       {"E", "robot.youngs_modulus"},
                                                       {"C_t", "effects.stokes_head.C_t"},
                                                       {"C_r", "effects.stokes_head.C_r"},
                                                       {"l_0", "effects.com_offset.offset"}};
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

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

}  // namespace

std::vector<std::string> modelErrorOverrides(
    const std::string& config_path, const std::vector<std::string>& overrides,
    const std::vector<std::pair<std::string, double>>& errors) {
  std::vector<std::string> out = overrides;
  if (errors.empty()) return out;
  const YAML::Node root = YAML::LoadFile(config_path);
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
            "': not a value of the config (use eps, E, C_t, C_r, l_0 or a section.field path)");
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

SteeringRunResult runSteering(const flagella::SimulationConfig& config,
                              const flagella::SessionOptions& session_options,
                              MassTransformerController& controller, double max_duration,
                              double sample_interval) {
  flagella::SimSession session(config, session_options);
  LcmHarness harness(session, controller, HarnessOptions{});
  SteeringRunResult result;
  double next_sample = 0.0;
  std::vector<double> miss;
  SteeringMode last_mode = SteeringMode::Waiting;
  const auto after_step = [&]() {
    const SteeringStatus& status = controller.status();
    if (status.mode != last_mode) {
      result.modes.emplace_back(session.time(), status.mode);
      last_mode = status.mode;
    }
    if (status.mode == SteeringMode::Waiting) return;
    const flagella::RodSnapshot s = session.snapshot();
    if (miss.empty()) {
      result.waypoints = controller.waypoints();
      miss.assign(result.waypoints.size(), std::numeric_limits<double>::infinity());
    }
    for (std::size_t i = 0; i < miss.size(); ++i)
      miss[i] = std::min(miss[i], (s.head_position - result.waypoints[i]).norm());
    if (session.time() + 1e-9 >= next_sample) {
      next_sample += sample_interval;
      SteeringSample sample;
      sample.time = session.time();
      sample.position = s.head_position;
      sample.estimate = controller.estimatedPosition();
      sample.motor = session.health().motor_applied;
      sample.slider = session.health().slider_position;
      sample.mode = status.mode;
      result.samples.push_back(sample);
    }
    if (status.mode == SteeringMode::Finished || status.mode == SteeringMode::Fault)
      harness.requestStop();
  };
  const HarnessReport report = harness.run(max_duration, after_step);
  result.total = static_cast<int>(controller.waypoints().size());
  result.miss = miss;
  for (double m : miss) {
    result.max_miss = std::max(result.max_miss, m);
    if (m <= controller.mission().tolerance) ++result.reached;
  }
  result.finished = controller.status().mode == SteeringMode::Finished;
  result.time = report.sim_time;
  result.wall_seconds = report.wall_seconds;
  result.halted = report.halted;
  result.cycles = controller.status().cycles;
  return result;
}

std::string steeringResultJson(const SteeringRunResult& r, const std::string& controller,
                               const std::string& mission) {
  std::ostringstream j;
  j << "{\n  \"controller\": \"" << controller << "\",\n  \"mission\": \"" << mission << "\",\n";
  j << "  \"reached\": " << r.reached << ",\n  \"total\": " << r.total << ",\n";
  j << "  \"max_miss_mm\": " << jsonNumber(r.max_miss * 1e3) << ",\n";
  j << "  \"miss_mm\": [";
  for (std::size_t i = 0; i < r.miss.size(); ++i)
    j << (i ? ", " : "") << jsonNumber(r.miss[i] * 1e3);
  j << "],\n  \"finished\": " << (r.finished ? "true" : "false") << ",\n";
  j << "  \"halted\": " << (r.halted ? "true" : "false") << ",\n";
  j << "  \"time_s\": " << jsonNumber(r.time) << ",\n  \"wall_s\": " << jsonNumber(r.wall_seconds)
    << ",\n  \"buckle_cycles\": " << r.cycles << ",\n  \"modes\": [";
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

}  // namespace flagella::control
