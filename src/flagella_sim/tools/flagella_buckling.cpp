// flagella_buckling: the motor rate at which the helical robot's flagellum buckles (docs/model.md
// 8.4.4), by bracketing and bisection over full runs; optionally swept over one config parameter
// (CSV + plot).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "plot_command.h"

namespace {

using flagella::SimulationConfig;
using flagella::ThresholdProbe;
using flagella::ThresholdResult;
using flagella::ThresholdSearchOptions;

struct Options {
  std::string config;
  std::vector<std::string> overrides;
  ThresholdSearchOptions search;
  std::string json, sweep, out_dir = "buckling_sweep", plot_script = FLAGELLA_BUCKLING_PLOT_SCRIPT;
  int jobs = 2;
  bool quiet = false;
};

std::string criterion(const SimulationConfig& c) {
  std::ostringstream s;
  s << "buckled when the largest angle between the head axis and the helix's principal axis over "
       "the last "
    << c.steady_fraction * 100.0 << " % of a " << c.duration << " s run exceeds "
    << c.buckling_tilt_deg << " deg (simulation.buckling_tilt_deg)";
  return s.str();
}

nlohmann::ordered_json resultJson(const SimulationConfig& c, const ThresholdResult& r) {
  nlohmann::ordered_json j;
  j["config"] = c.source;
  j["found"] = r.found;
  j["buckling_threshold_rpm"] = r.found ? nlohmann::ordered_json(r.threshold) : nullptr;
  j["bracket_rpm"] = r.found ? nlohmann::ordered_json({r.low, r.high}) : nullptr;
  if (!r.found) j["message"] = r.message;
  nlohmann::ordered_json rule;
  rule["definition"] = criterion(c);
  rule["buckling_tilt_deg"] = c.buckling_tilt_deg;
  rule["duration_s"] = c.duration;
  rule["steady_fraction"] = c.steady_fraction;
  j["criterion"] = rule;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const ThresholdProbe& p : r.runs) {
    nlohmann::ordered_json run;
    run["omega_rpm"] = p.rate;
    run["max_tilt_deg"] = p.indicator;
    run["buckled"] = p.above;
    run["wall_s"] = p.wall_seconds;
    run["failed"] = p.failed;
    run["error"] = p.error;
    runs.push_back(run);
  }
  j["runs"] = runs;
  return j;
}

void printRun(const std::string& prefix, const ThresholdProbe& p) {
  if (p.failed)
    std::fprintf(stderr, "%s%8.3f rpm: FAILED (%s)\n", prefix.c_str(), p.rate, p.error.c_str());
  else
    std::fprintf(stderr, "%s%8.3f rpm: max tilt %6.2f deg -> %s (%.1f s)\n", prefix.c_str(), p.rate,
                 p.indicator, p.above ? "buckled" : "helical", p.wall_seconds);
}

ThresholdResult search(const SimulationConfig& c, const Options& o, const std::string& prefix) {
  static std::mutex print;  // one lock for every search: sweep threads print whole lines
  return flagella::findThreshold([&](double rpm) { return flagella::runBucklingProbe(c, rpm); },
                                 o.search,
                                 [&](const ThresholdProbe& p) {
                                   if (o.quiet) return;
                                   std::lock_guard<std::mutex> lock(print);
                                   printRun(prefix, p);
                                 });
}

int single(const Options& o) {
  const SimulationConfig c = flagella::loadSimulationConfig(o.config, o.overrides);
  if (!o.quiet) std::fprintf(stderr, "criterion: %s\n", criterion(c).c_str());
  const ThresholdResult r = search(c, o, "  ");
  if (r.found)
    std::printf("buckling threshold: %.3f rpm (bracket %.3f .. %.3f rpm, %zu runs)\n", r.threshold,
                r.low, r.high, r.runs.size());
  else
    std::printf("no buckling threshold: %s\n", r.message.c_str());
  if (!o.json.empty()) {
    std::ofstream out(o.json);
    out << resultJson(c, r).dump(2) << "\n";
    if (!out) throw std::runtime_error("--json: cannot write " + o.json);
    std::printf("wrote %s\n", o.json.c_str());
  }
  return r.found ? 0 : 3;
}

// "robot.filament_radius=1e-3,2e-3" -> key and values (each checked by loading the config).
std::pair<std::string, std::vector<std::string>> parseSweep(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw std::invalid_argument("--sweep must look like section.field=v1,v2,..., got '" + text +
                                "'");
  std::vector<std::string> values;
  std::stringstream list(text.substr(eq + 1));
  for (std::string v; std::getline(list, v, ',');)
    if (!v.empty()) values.push_back(v);
  return {text.substr(0, eq), values};
}

int sweep(const Options& o) {
  const auto [key, values] = parseSweep(o.sweep);
  std::vector<SimulationConfig> configs;  // all validated before any run
  for (const std::string& v : values) {
    std::vector<std::string> overrides = o.overrides;
    overrides.push_back(key + "=" + v);
    configs.push_back(flagella::loadSimulationConfig(o.config, overrides));
  }
  if (!o.quiet) std::fprintf(stderr, "criterion: %s\n", criterion(configs.front()).c_str());
  std::vector<ThresholdResult> results(values.size());
  std::mutex mutex;
  size_t next = 0;
  auto worker = [&] {
    for (;;) {
      size_t i;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (next >= values.size()) return;
        i = next++;
      }
      results[i] = search(configs[i], o, "  [" + key + " = " + values[i] + "] ");
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::max(1, o.jobs); ++j) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  std::filesystem::create_directories(o.out_dir);
  const std::string table = o.out_dir + "/buckling_sweep.csv";
  std::ofstream csv(table);
  csv << "parameter,value,buckling_threshold_rpm,bracket_low_rpm,bracket_high_rpm,runs,found,"
         "message\n";
  for (size_t i = 0; i < values.size(); ++i) {
    const ThresholdResult& r = results[i];
    csv << key << "," << values[i] << "," << (r.found ? std::to_string(r.threshold) : "") << ","
        << (r.found ? std::to_string(r.low) : "") << "," << (r.found ? std::to_string(r.high) : "")
        << "," << r.runs.size() << "," << (r.found ? 1 : 0) << ",\"" << r.message << "\"\n";
    std::printf("%s = %s: %s\n", key.c_str(), values[i].c_str(),
                r.found ? (std::to_string(r.threshold) + " rpm").c_str() : r.message.c_str());
  }
  csv.close();
  std::printf("sweep table: %s\n", table.c_str());
  flagella::cli::plotTable(o.plot_script, table, o.out_dir + "/buckling_sweep.png");
  for (const ThresholdResult& r : results)
    if (!r.found) return 3;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "flagella_buckling: the motor rate at which the flagellum buckles (bracketing + bisection)"};
  Options o;
  app.add_option("config", o.config, "simulation config (YAML), e.g. config/helical_gimbal.yaml")
      ->required();
  app.add_option("--set", o.overrides, "override a config field: section.field=value (repeatable)");
  app.add_option("--low", o.search.low, "first lower guess [rpm], > 0")->capture_default_str();
  app.add_option("--high", o.search.high, "first upper guess [rpm], > low")->capture_default_str();
  app.add_option("--tolerance", o.search.tolerance, "stop when the bracket is narrower [rpm], > 0")
      ->capture_default_str();
  app.add_option("--min-rpm", o.search.min_rate, "smallest rate tried [rpm]")
      ->capture_default_str();
  app.add_option("--max-rpm", o.search.max_rate, "largest rate tried [rpm]")->capture_default_str();
  app.add_option("--max-runs", o.search.max_runs, "give up after this many runs")
      ->capture_default_str();
  app.add_option("--json", o.json, "write the threshold, bracket, criterion and runs as JSON");
  app.add_option("--sweep", o.sweep,
                 "sweep mode: section.field=v1,v2,... (a threshold per value, CSV + plot)");
  app.add_option("--out", o.out_dir, "sweep mode: output folder")->capture_default_str();
  app.add_option("--jobs", o.jobs, "sweep mode: values searched in parallel")
      ->capture_default_str();
  app.add_option("--plot-script", o.plot_script, "sweep mode: matplotlib script ('' to skip)");
  app.add_flag("--quiet", o.quiet, "no progress lines");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  try {
    flagella::validate(o.search);
    return o.sweep.empty() ? single(o) : sweep(o);
  } catch (const std::invalid_argument& e) {  // ConfigError included
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 3;
  }
}
