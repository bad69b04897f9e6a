// flagella_buckling: the motor rate at which the helical robot's flagellum buckles (docs/model.md
// 8.4.4): where the growth rate of its slow tilt changes sign (--method growth, the definition),
// or where a run of fixed length first shows a large tilt (--method tilt, bracketing and
// bisection; the secondary "visibly buckled within T s"); optionally swept over one config
// parameter (CSV + plot).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/exact_json.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/tool_main.h"
#include "growth_report.h"
#include "plot_command.h"
#include "tilt_report.h"

namespace {

using flagella::SimulationConfig;
using flagella::ThresholdProbe;
using flagella::ThresholdResult;
using flagella::ThresholdSearchOptions;
using flagella::cli::criterion;
using flagella::cli::decodeSearch;
using flagella::cli::encodeSearch;
using flagella::cli::resultJson;
using flagella::cli::Search;

struct Options {
  std::string config;
  std::vector<std::string> overrides;
  ThresholdSearchOptions search;
  std::string method = "growth";
  flagella::GrowthProbeOptions growth;
  double relative_tolerance = 0.01;
  std::string json, sweep, out_dir = "buckling_sweep", plot_script = FLAGELLA_BUCKLING_PLOT_SCRIPT;
  std::string growth_plot_script = FLAGELLA_GROWTH_PLOT_SCRIPT;
  bool out_given = false;  ///< --out given: a single growth search writes its table there
  int jobs = flagella::defaultJobs();
  int refine = 0;  ///< > 0: also the smoothed threshold over 2 refine + 1 grid rates
  bool quiet = false;
};

/// Rate ratio of the refinement runs: the calibration's grid (docs/model.md 8.4.5).
constexpr double kRefineGridRatio = 1.02;
constexpr int kRefineMoves = 4;  ///< window moves toward a crossing outside it

bool usesGrowth(const Options& o) { return o.method == "growth"; }

flagella::GrowthThresholdOptions growthSearch(const Options& o) {
  flagella::GrowthThresholdOptions g;
  g.low = o.search.low;
  g.high = o.search.high;
  g.min_rate = o.search.min_rate;
  g.max_rate = o.search.max_rate;
  g.tolerance = o.relative_tolerance;
  g.max_runs = o.search.max_runs;
  return g;
}

void printRun(const std::string& prefix, const ThresholdProbe& p) {
  if (p.failed)
    std::fprintf(stderr, "%s%8.3f rpm: FAILED (%s)\n", prefix.c_str(), p.rate, p.error.c_str());
  else
    std::fprintf(stderr, "%s%8.3f rpm: max tilt %6.2f deg -> %s (%.1f s)\n", prefix.c_str(), p.rate,
                 p.indicator, p.above ? "buckled" : "helical", p.wall_seconds);
}

Search search(const SimulationConfig& c, const Options& o, const std::string& prefix) {
  static std::mutex print;  // one lock for every search: sweep threads print whole lines
  if (usesGrowth(o)) {
    Search s;
    s.growth = flagella::findGrowthThreshold(
        [&](double rpm) { return flagella::runGrowthProbe(c, rpm, o.growth); }, growthSearch(o),
        [&](const flagella::GrowthProbe& p) {
          if (o.quiet) return;
          std::lock_guard<std::mutex> lock(print);
          std::fprintf(stderr, "%s%s\n", prefix.c_str(), flagella::cli::growthRunLine(p).c_str());
        });
    return s;
  }
  auto probe = [&](double rpm) { return flagella::runBucklingProbe(c, rpm); };
  auto progress = [&](const ThresholdProbe& p) {
    if (o.quiet) return;
    std::lock_guard<std::mutex> lock(print);
    printRun(prefix, p);
  };
  Search s;
  s.bisection = flagella::findThreshold(probe, o.search, progress);
  if (o.refine > 0 && s.bisection.found)
    s.refined = flagella::windowThreshold(probe, s.bisection.threshold, kRefineGridRatio, o.refine,
                                          c.buckling_tilt_deg, kRefineMoves, progress);
  return s;
}

void writeJson(const Options& o, const nlohmann::ordered_json& j) {
  if (o.json.empty() || !flagella::isRootRank()) return;  // under mpirun every rank searches
  std::ofstream out(o.json);
  out << j.dump(2) << "\n";
  if (!out) throw std::runtime_error("--json: cannot write " + o.json);
  std::printf("wrote %s\n", o.json.c_str());
}

int singleGrowth(const Options& o, const SimulationConfig& c) {
  if (!o.quiet)
    std::fprintf(stderr, "threshold: %s\n", flagella::cli::growthDefinition(o.growth).c_str());
  const Search s = search(c, o, "  ");
  const flagella::GrowthThreshold& g = s.growth;
  if (g.found)
    std::printf(
        "buckling threshold: %.3f +- %.3f rpm (sigma changes sign between %.3f and %.3f "
        "rpm, %zu runs of %.4g flagellum turns)\n",
        g.threshold, g.uncertainty, g.low, g.high, g.runs.size(), o.growth.observe_turns);
  else
    std::printf("no buckling threshold: %s\n", g.message.c_str());
  for (const flagella::GrowthProbe& p : g.runs)  // runs at the threshold have sigma near 0
    if (!p.failed && !p.trusted() &&
        !(g.found && std::abs(p.rate - g.threshold) <= 2.0 * g.uncertainty))
      std::printf("caution: the run at %.3f rpm is too short to trust its sign (--observe-turns)\n",
                  p.rate);
  nlohmann::ordered_json j = flagella::cli::growthJson(g, o.growth);
  j["config"] = c.source;
  writeJson(o, j);
  if (o.out_given && flagella::isRootRank() && !g.runs.empty()) {
    std::filesystem::create_directories(o.out_dir);
    const std::string table = o.out_dir + "/growth_rates.csv";
    flagella::cli::writeGrowthCsv(table, g);
    std::printf("growth rates: %s\n", table.c_str());
    if (!o.plot_script.empty())
      flagella::cli::plotTable(o.growth_plot_script, table, o.out_dir + "/growth_rates.png",
                               "growth-rate plot");
  }
  return g.found ? 0 : 3;
}

int single(const Options& o) {
  const SimulationConfig c = flagella::loadSimulationConfig(o.config, o.overrides);
  if (usesGrowth(o)) return singleGrowth(o, c);
  if (!o.quiet) std::fprintf(stderr, "criterion: %s\n", criterion(c).c_str());
  const Search s = search(c, o, "  ");
  const ThresholdResult& r = s.bisection;
  if (r.found)
    std::printf("buckling threshold: %.3f rpm (bracket %.3f .. %.3f rpm, %zu runs)\n", r.threshold,
                r.low, r.high, r.runs.size());
  else
    std::printf("no buckling threshold: %s\n", r.message.c_str());
  if (o.refine > 0 && r.found) {
    if (std::isfinite(s.refined.threshold))
      std::printf("smoothed threshold: %.3f rpm (%zu more runs)\n", s.refined.threshold,
                  s.refined.runs.size());
    else
      std::printf("no smoothed threshold: %s\n", s.refined.message.c_str());
  }
  writeJson(o, resultJson(c, s, o.refine));
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
  flagella::requireJobs("--jobs", o.jobs);
  const auto [key, values] = parseSweep(o.sweep);
  std::vector<SimulationConfig> configs;  // all validated before any run
  for (const std::string& v : values) {
    std::vector<std::string> overrides = o.overrides;
    overrides.push_back(key + "=" + v);
    configs.push_back(flagella::loadSimulationConfig(o.config, overrides));
  }
  if (!o.quiet)
    std::fprintf(stderr, "criterion: %s\n",
                 usesGrowth(o) ? flagella::cli::growthDefinition(o.growth).c_str()
                               : criterion(configs.front()).c_str());
  // On this rank's threads, or spread over mpirun's ranks (every rank gets every search).
  const std::vector<std::string> results =
      flagella::distributedFor(static_cast<int>(values.size()), o.jobs, [&](int i) {
        return encodeSearch(search(configs[i], o, "  [" + key + " = " + values[i] + "] "));
      });
  std::vector<Search> searches;
  int status = 0;  // 3 when a search found no threshold
  for (const std::string& r : results) {
    searches.push_back(decodeSearch(r));
    if (!(usesGrowth(o) ? searches.back().growth.found : searches.back().bisection.found))
      status = 3;
  }
  if (!flagella::isRootRank()) return status;  // rank 0 writes the table
  std::filesystem::create_directories(o.out_dir);
  const std::string table = o.out_dir + "/buckling_sweep.csv";
  std::ofstream csv(table);
  csv << "parameter,value,buckling_threshold_rpm,bracket_low_rpm,bracket_high_rpm,runs,found,"
         "message,smoothed_threshold_rpm\n";
  for (size_t i = 0; i < values.size(); ++i) {
    ThresholdResult r = searches[i].bisection;
    if (usesGrowth(o)) {  // the same columns: the bracket is where sigma changes sign
      const flagella::GrowthThreshold& g = searches[i].growth;
      r.found = g.found;
      r.threshold = g.threshold;
      r.low = g.low;
      r.high = g.high;
      r.runs.assign(g.runs.size(), {});
      r.message = g.message;
    }
    const double refined = searches[i].refined.threshold;
    csv << key << "," << values[i] << "," << (r.found ? std::to_string(r.threshold) : "") << ","
        << (r.found ? std::to_string(r.low) : "") << "," << (r.found ? std::to_string(r.high) : "")
        << "," << r.runs.size() << "," << (r.found ? 1 : 0) << ",\"" << r.message << "\","
        << (std::isfinite(refined) ? std::to_string(refined) : "") << "\n";
    std::printf("%s = %s: %s\n", key.c_str(), values[i].c_str(),
                r.found ? (std::to_string(r.threshold) + " rpm").c_str() : r.message.c_str());
  }
  csv.close();
  std::printf("sweep table: %s\n", table.c_str());
  flagella::cli::plotTable(o.plot_script, table, o.out_dir + "/buckling_sweep.png");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  const flagella::MpiScope mpi;  // under mpirun: --sweep spreads its searches over the ranks
  CLI::App app{
      "flagella_buckling: the motor rate at which the flagellum buckles (where its tilt's growth "
      "rate changes sign)"};
  Options o;
  app.add_option("config", o.config, "simulation config (YAML), e.g. config/helical_gimbal.yaml")
      ->required();
  app.add_option("--set", o.overrides, "override a config field: section.field=value (repeatable)");
  app.add_option("--low", o.search.low, "first lower guess [rpm], > 0")->capture_default_str();
  app.add_option("--high", o.search.high, "first upper guess [rpm], > low")->capture_default_str();
  app.add_option("--method", o.method,
                 "growth: where the growth rate of the slow tilt changes sign (the threshold); "
                 "tilt: where a run of simulation.duration first shows a tilt above "
                 "simulation.buckling_tilt_deg (visibly buckled within that time)")
      ->check(CLI::IsMember({"growth", "tilt"}))
      ->capture_default_str();
  app.add_option("--observe-turns", o.growth.observe_turns,
                 "growth: run length T in turns of the flagellum, > --settle-turns + 2")
      ->capture_default_str();
  app.add_option("--settle-turns", o.growth.settle_turns,
                 "growth: the fit window starts here [flagellum turns], after the spin-up's "
                 "transients")
      ->capture_default_str();
  app.add_option("--small-tilt", o.growth.small_tilt_deg,
                 "growth: the fit window ends where the slow tilt passes this [deg], in (0, 45)")
      ->capture_default_str();
  app.add_option("--rel-tolerance", o.relative_tolerance,
                 "growth: stop when the bracket is narrower than this fraction of the rate")
      ->capture_default_str();
  app.add_option("--tolerance", o.search.tolerance,
                 "tilt: stop when the bracket is narrower [rpm], > 0")
      ->capture_default_str();
  app.add_option("--min-rpm", o.search.min_rate, "smallest rate tried [rpm]")
      ->capture_default_str();
  app.add_option("--max-rpm", o.search.max_rate, "largest rate tried [rpm]")->capture_default_str();
  app.add_option("--max-runs", o.search.max_runs, "give up after this many runs")
      ->capture_default_str();
  app.add_option("--json", o.json, "write the threshold, bracket, criterion and runs as JSON");
  app.add_option("--sweep", o.sweep,
                 "sweep mode: section.field=v1,v2,... (a threshold per value, CSV + plot)");
  app.add_option("--out", o.out_dir,
                 "output folder: the sweep's table and plot; a single growth search writes sigma "
                 "against the rate there when given (growth_rates.csv, .png)")
      ->capture_default_str();
  app.add_option("--jobs", o.jobs, "sweep mode: values searched in parallel, in [1, 256]")
      ->capture_default_str();
  app.add_option("--plot-script", o.plot_script, "sweep mode: matplotlib script ('' to skip)");
  app.add_option(
         "--refine", o.refine,
         "also run the 2N+1 rates 1.02^k rpm nearest the threshold (N >= 2) and report where "
         "their tilt, averaged over neighbouring rates, crosses the criterion (the "
         "calibration's estimate; 0: off)")
      ->check(CLI::Validator(
          [](std::string& text) {
            const int n = std::atoi(text.c_str());
            return text == "0" || (n >= 2 && n <= 20 && std::to_string(n) == text)
                       ? std::string()
                       : "must be 0 (off) or an integer in [2, 20], got " + text;
          },
          "0 (off) or INT in [2, 20]"))
      ->capture_default_str();
  app.add_flag("--quiet", o.quiet, "no progress lines");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  o.out_given = app.count("--out") > 0;
  return flagella::cli::runGuarded([&] {
    flagella::validate(o.search);
    if (usesGrowth(o)) {
      flagella::validate(o.growth);
      flagella::validate(growthSearch(o));
      if (o.refine > 0) throw std::invalid_argument("--refine needs --method tilt");
    }
    return o.sweep.empty() ? single(o) : sweep(o);
  });
}
