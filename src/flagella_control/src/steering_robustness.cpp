// Robustness runs of the mass-transformer closed loop; see the header.
#include "flagella_control/steering_robustness.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>

#include "flagella_control/validation.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::control {

namespace {

const char* const kContext = "robustness options";

std::string factorsText(const std::vector<std::pair<std::string, double>>& factors) {
  if (factors.empty()) return "nominal";
  std::ostringstream out;
  out.precision(3);
  for (std::size_t i = 0; i < factors.size(); ++i)
    out << (i ? " " : "") << factors[i].first << "x" << factors[i].second;
  return out.str();
}

// Median of a copy.
double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

void RobustnessOptions::validate() const {
  if (runs < 1 || runs > 10000)
    throw std::invalid_argument("robustness options: runs must be in [1, 10000], got " +
                                std::to_string(runs));
  requireInRange(kContext, "error", error, 0.0, 0.9);
  if (jobs < 1 || jobs > flagella::kMaxJobs)
    throw std::invalid_argument("robustness options: jobs must be in [1, " +
                                std::to_string(flagella::kMaxJobs) + "], got " +
                                std::to_string(jobs));
  requireInRange(kContext, "max_duration", max_duration, 1.0, 1e5);
  if (keys.empty()) throw std::invalid_argument("robustness options: keys must not be empty");
}

std::vector<std::pair<std::string, double>> drawModelErrors(const RobustnessOptions& options,
                                                            unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution coin(0.5);
  std::vector<std::pair<std::string, double>> factors;
  for (const std::string& key : options.keys)
    factors.emplace_back(key, coin(rng) ? 1.0 + options.error : 1.0 - options.error);
  return factors;
}

RobustnessReport runRobustness(const RobustnessOptions& options,
                               const SteeringCalibration& calibration,
                               const std::vector<NamedMission>& missions,
                               const SteeringGains& gains,
                               const std::function<void(const std::string&)>& progress) {
  options.validate();
  if (missions.empty()) throw std::invalid_argument("robustness options: no mission given");
  const auto wall_start = std::chrono::steady_clock::now();
  RobustnessReport report;
  for (const NamedMission& m : missions) {
    report.missions.push_back(m.name);
    report.tolerances.push_back(m.mission.tolerance);
  }
  const bool several = missions.size() > 1;
  const flagella::SimulationConfig nominal =
      flagella::loadSimulationConfig(options.config_path, options.overrides);
  // Every key must name a value of the config before the reference runs (minutes) start: a
  // misspelt key, or k_t without effects.dc_motor, fails here as bad input, not in every run.
  flagella::loadSimulationConfig(options.config_path,
                                 modelErrorOverrides(options.config_path, options.overrides,
                                                     drawModelErrors(options, options.first_seed)));
  // Each mission's open-loop schedule: the controller on the nominal model with perfect sensors.
  std::vector<std::vector<RecordedCommand>> schedules(missions.size());
  if (options.replay) {
    flagella::SessionOptions perfect = steeringSessionOptions(nominal, calibration, 0);
    perfect.imu.orientation_noise_std = perfect.imu.gyro_noise_std = 0.0;
    perfect.accelerometer.noise_std = 0.0;
    perfect.camera.noise_std = perfect.camera.height_noise_std = 0.0;
    report.references.resize(missions.size());
    flagella::parallelFor(static_cast<int>(missions.size()), options.jobs, [&](int m) {
      MassTransformerController controller(missions[m].mission, calibration, gains);
      report.references[m] =
          runSteering(nominal, perfect, controller, options.max_duration, 0.5, &schedules[m]);
      report.references[m].samples.clear();
    });
    for (std::size_t m = 0; m < missions.size(); ++m) {
      const SteeringRunResult& reference = report.references[m];
      if (reference.waypoints.size() != missions[m].mission.points.size())
        throw std::runtime_error((several ? missions[m].name + ": " : std::string()) +
                                 "the reference run never placed its waypoints: max_duration (" +
                                 std::to_string(options.max_duration) +
                                 " s) ends before the mission's course_time");
      if (progress)
        progress(
            (several ? missions[m].name + ": " : std::string()) +
            "reference (nominal model, perfect sensors): " + std::to_string(reference.reached) +
            " of " + std::to_string(reference.total) + " reached, open-loop schedule of " +
            std::to_string(schedules[m].size()) + " commands");
    }
  }

  for (std::size_t m = 0; m < missions.size(); ++m)
    for (int i = 0; i < options.runs; ++i) {
      const unsigned seed = options.first_seed + static_cast<unsigned>(i);
      if (options.nominal) report.runs.push_back({"nominal closed", m, seed, {}, {}, {}});
      const auto factors = drawModelErrors(options, seed);
      report.runs.push_back({"mismatched closed", m, seed, factors, {}, {}});
      if (options.replay) report.runs.push_back({"mismatched open", m, seed, factors, {}, {}});
    }
  std::atomic<int> done{0};
  std::mutex print;
  flagella::parallelFor(static_cast<int>(report.runs.size()), options.jobs, [&](int k) {
    RobustnessRun& run = report.runs[k];
    const WaypointMission& mission = missions[run.mission].mission;
    try {
      const flagella::SimulationConfig config = flagella::loadSimulationConfig(
          options.config_path,
          modelErrorOverrides(options.config_path, options.overrides, run.factors));
      const flagella::SessionOptions sensors =
          steeringSessionOptions(config, calibration, run.seed);
      if (run.kind == "mismatched open") {
        run.result = runOpenLoop(config, sensors, schedules[run.mission], calibration.park_position,
                                 report.references[run.mission].waypoints, mission.tolerance,
                                 options.max_duration);
      } else {
        MassTransformerController controller(mission, calibration, gains);
        run.result = runSteering(config, sensors, controller, options.max_duration);
      }
      run.result.samples.clear();
    } catch (const std::exception& e) {
      run.error = e.what();
    }
    const int finished = ++done;
    if (progress) {
      char line[640];
      std::snprintf(
          line, sizeof line,
          "[%d/%zu] %s%s%s, seed %u (%s): %d of %d reached (%d in order), max miss "
          "%.1f mm, %.0f s simulated%s%s",
          finished, report.runs.size(), several ? report.missions[run.mission].c_str() : "",
          several ? ", " : "", run.kind.c_str(), run.seed, factorsText(run.factors).c_str(),
          run.result.reached, run.result.total, run.result.reached_in_order,
          run.result.max_miss * 1e3, run.result.time, run.result.halted ? ", simulator halted" : "",
          run.error.empty() ? "" : (", error: " + run.error).c_str());
      const std::lock_guard<std::mutex> lock(print);
      progress(line);
    }
  });
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return report;
}

RobustnessReport runRobustness(const RobustnessOptions& options,
                               const SteeringCalibration& calibration,
                               const WaypointMission& mission, const SteeringGains& gains,
                               const std::function<void(const std::string&)>& progress) {
  return runRobustness(options, calibration, {{"mission", mission}}, gains, progress);
}

namespace {

constexpr std::size_t kAllMissions = static_cast<std::size_t>(-1);
const char* const kKinds[] = {"nominal closed", "mismatched closed", "mismatched open"};

// A run that reached every waypoint.
bool succeeded(const RobustnessRun& r) {
  return r.error.empty() && r.result.total > 0 && r.result.reached == r.result.total;
}

// The figures of one kind of run (of one mission, or of all) in the summary tables.
struct KindFigures {
  int runs = 0, successes = 0, in_order = 0, reached = 0, reached_in_order = 0, total = 0;
  int halts = 0;
  long motor_stop_retries = 0;
  std::vector<double> misses, mission_times, slider_travels;
};

KindFigures kindFigures(const RobustnessReport& report, const std::string& kind,
                        std::size_t mission = kAllMissions) {
  KindFigures f;
  for (const RobustnessRun& r : report.runs) {
    if (r.kind != kind || (mission != kAllMissions && r.mission != mission)) continue;
    ++f.runs;
    const SteeringRunResult& x = r.result;
    const bool ok = succeeded(r);
    const bool ordered = ok && x.reached_in_order == x.total;
    f.successes += ok ? 1 : 0;
    f.in_order += ordered ? 1 : 0;
    f.reached += x.reached;
    f.reached_in_order += x.reached_in_order;
    f.total += x.total;
    f.halts += x.halted ? 1 : 0;
    f.motor_stop_retries += x.motor_stop_retries;
    for (double m : x.miss) f.misses.push_back(m);
    if (ordered && !x.reach_time.empty()) f.mission_times.push_back(x.reach_time.back());
    if (!std::isnan(x.slider_low)) f.slider_travels.push_back(x.slider_high - x.slider_low);
  }
  return f;
}

double worstOf(const std::vector<double>& v) {
  return v.empty() ? NAN : *std::max_element(v.begin(), v.end());
}

// "within 18.0 mm" or, when the missions' tolerances differ, "within each mission's tolerance".
std::string toleranceText(const std::vector<double>& tolerances) {
  char text[96];
  const auto [low, high] = std::minmax_element(tolerances.begin(), tolerances.end());
  if (*low == *high)
    std::snprintf(text, sizeof text, "within %.1f mm", *low * 1e3);
  else
    std::snprintf(text, sizeof text, "within each mission's tolerance (%.1f-%.1f mm)", *low * 1e3,
                  *high * 1e3);
  return text;
}

// Per mission and kind: runs reaching every waypoint, waypoints, worst miss.
void printMissionTable(const RobustnessReport& report, std::ostringstream& out) {
  char line[512];
  out << "\nper mission\n";
  std::snprintf(line, sizeof line, "%-18s %-18s %5s %9s %13s %9s %13s\n", "mission", "kind", "runs",
                "success", "waypoints", "in order", "worst miss");
  out << line;
  for (std::size_t m = 0; m < report.missions.size(); ++m)
    for (const char* kind : kKinds) {
      const KindFigures f = kindFigures(report, kind, m);
      if (f.runs == 0) continue;
      std::snprintf(line, sizeof line,
                    "%-18s %-18s %5d %4d of %-3d %6d of %-4d %3d, %-4d %8.1f mm\n",
                    report.missions[m].c_str(), kind, f.runs, f.successes, f.runs, f.reached,
                    f.total, f.in_order, f.reached_in_order, worstOf(f.misses) * 1e3);
      out << line;
    }
}

// Per seed and kind: the missions whose every waypoint was reached.
void printSeedTable(const RobustnessReport& report, std::ostringstream& out) {
  std::map<std::pair<std::string, unsigned>, std::pair<int, std::vector<std::string>>> by_seed;
  for (const RobustnessRun& r : report.runs) {
    auto& [passed, failed] = by_seed[{r.kind, r.seed}];
    if (succeeded(r))
      ++passed;
    else
      failed.push_back(report.missions[r.mission]);
  }
  out << "\nmissions passed per seed (every waypoint reached)\n";
  for (const char* kind : kKinds)
    for (const auto& [key, figures] : by_seed) {
      if (key.first != kind) continue;
      const auto& [passed, failed] = figures;
      std::string failing;
      for (const std::string& name : failed) failing += (failing.empty() ? "" : ", ") + name;
      char line[256];
      std::snprintf(line, sizeof line, "%-18s seed %-4u %3d of %zu", kind, key.second, passed,
                    report.missions.size());
      out << line << (failing.empty() ? "" : " (missed: " + failing + ")") << "\n";
    }
}

}  // namespace

std::string robustnessSummary(const RobustnessReport& report) {
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof line, "%-18s %5s %9s %13s %9s %13s %13s %11s %13s %6s %8s\n", "kind",
                "runs", "success", "waypoints", "in order", "median miss", "worst miss",
                "time to end", "slider travel", "halts", "retries");
  out << line;
  for (const char* kind : kKinds) {
    const KindFigures f = kindFigures(report, kind);
    if (f.runs == 0) continue;
    std::snprintf(line, sizeof line,
                  "%-18s %5d %8.0f%% %6d of %-4d %3d, %-4d %10.1f mm %10.1f mm %9.0f s %10.2f mm "
                  "%6d %8ld\n",
                  kind, f.runs, 100.0 * f.successes / f.runs, f.reached, f.total, f.in_order,
                  f.reached_in_order, median(f.misses) * 1e3, worstOf(f.misses) * 1e3,
                  median(f.mission_times), median(f.slider_travels) * 1e3, f.halts,
                  f.motor_stop_retries);
    out << line;
  }
  out << "success: every waypoint passed " << toleranceText(report.tolerances)
      << " by the true head path; misses are closest approaches per waypoint; in order: runs "
         "with every waypoint reached in the mission's order, and waypoints so reached; time to "
         "end: median time the last waypoint was reached over the runs in order; slider travel: "
         "median range of slider positions a run used; halts: runs the simulator halted; "
         "retries: steps that failed after subdivision and were retried with the motor stopped\n";
  if (report.missions.size() > 1) {
    printMissionTable(report, out);
    printSeedTable(report, out);
  }
  return out.str();
}

namespace {

void writeRunJson(const RobustnessReport& report, const RobustnessRun& r, std::ostringstream& j) {
  j << "    {\"kind\": \"" << r.kind << "\", \"mission\": \""
    << jsonEscaped(report.missions[r.mission]) << "\", \"seed\": " << r.seed << ", \"factors\": {";
  for (std::size_t k = 0; k < r.factors.size(); ++k)
    j << (k ? ", " : "") << "\"" << r.factors[k].first << "\": " << jsonNumber(r.factors[k].second);
  j << "}, \"reached\": " << r.result.reached
    << ", \"reached_in_order\": " << r.result.reached_in_order << ", \"total\": " << r.result.total
    << ", \"max_miss_mm\": " << jsonNumber(r.result.max_miss * 1e3) << ", \"miss_mm\": [";
  for (std::size_t k = 0; k < r.result.miss.size(); ++k)
    j << (k ? ", " : "") << jsonNumber(r.result.miss[k] * 1e3);
  j << "], \"reach_time_s\": [";
  for (std::size_t k = 0; k < r.result.reach_time.size(); ++k)
    j << (k ? ", " : "") << jsonNumber(r.result.reach_time[k]);
  j << "], \"slider_low_m\": " << jsonNumber(r.result.slider_low)
    << ", \"slider_high_m\": " << jsonNumber(r.result.slider_high)
    << ", \"subdivided_steps\": " << r.result.subdivided_steps
    << ", \"damped_steps\": " << r.result.damped_steps
    << ", \"motor_stop_retries\": " << r.result.motor_stop_retries
    << ", \"time_s\": " << jsonNumber(r.result.time)
    << ", \"wall_s\": " << jsonNumber(r.result.wall_seconds)
    << ", \"halted\": " << (r.result.halted ? "true" : "false") << ", \"error\": \""
    << jsonEscaped(r.error) << "\"}";
}

}  // namespace

std::string robustnessJson(const RobustnessReport& report) {
  std::ostringstream j;
  j << "{\n  \"wall_s\": " << jsonNumber(report.wall_seconds) << ",\n  \"missions\": [";
  for (std::size_t m = 0; m < report.missions.size(); ++m) {
    j << (m ? ",\n" : "\n") << "    {\"name\": \"" << jsonEscaped(report.missions[m])
      << "\", \"tolerance_mm\": " << jsonNumber(report.tolerances[m] * 1e3) << ", \"reference\": ";
    if (report.references.empty()) {
      j << "null}";
      continue;
    }
    const SteeringRunResult& ref = report.references[m];
    j << "{\"reached\": " << ref.reached << ", \"total\": " << ref.total
      << ", \"max_miss_mm\": " << jsonNumber(ref.max_miss * 1e3) << "}}";
  }
  j << "\n  ],\n  \"runs\": [";
  for (std::size_t i = 0; i < report.runs.size(); ++i) {
    j << (i ? ",\n" : "\n");
    writeRunJson(report, report.runs[i], j);
  }
  j << "\n  ]\n}\n";
  return j.str();
}

}  // namespace flagella::control
