// flagella_identify: from measured data and a baseline robot config to a discovery report
// (calibrate, diagnose, select a physical effect, measure the held-out gain).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "flagella_identify/bag_reader.h"
#include "flagella_identify/calibration.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"
#include "flagella_identify/report.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/tool_main.h"

using namespace flagella;
using namespace flagella::identify;

namespace {

/// The default free parameters that the config actually has (the discovery cases' own,
/// docs/model.md 7.6: the head's C_t and C_r only on a single-flagellum robot).
std::vector<std::string> defaultFree(const YAML::Node& config) {
  std::vector<std::string> free;
  for (const std::string& name : caseFreeParameters(config))
    if (configField(config, name).IsScalar()) free.push_back(name);
  return free;
}

/// --calibrate-only: fit the free parameters on every experiment and write the calibration report.
void runCalibration(const MeasuredData& data, const YAML::Node& baseline, const std::string& config,
                    const std::vector<std::string>& data_files, const CalibrationOptions& options,
                    const std::string& out_dir) {
  const CalibrationResult result = calibrate(data, baseline, config, options);
  std::printf("\ncalibrated (chi^2 %.4g over %d residuals, RMS z %.3g):\n",
              result.quality.chi_square, result.quality.count, result.quality.rms_z);
  for (size_t i = 0; i < result.parameters.size(); ++i) {
    const FitParameter& p = result.parameters[i];
    std::printf("  %s = %.6g +- %.2g %s (start %.6g)\n", p.name.c_str(), p.value, p.uncertainty,
                p.unit.c_str(), result.start[i].value);
  }
  for (const std::string& w : offTheMap(result.parameters))
    std::printf("  warning: %s: this calibration is at the edge of its range\n", w.c_str());
  std::fflush(stdout);
  for (const std::string& f : writeCalibrationReport(result, data, data_files, config, out_dir))
    std::cout << "wrote " << f << "\n";
}

/// A temporary folder for the outputs of MPI ranks other than 0, removed with its contents.
struct ScratchFolder {
  std::string path;
  ScratchFolder() {
    char name[] = "/tmp/flagella_identify_rankXXXXXX";
    const char* made = mkdtemp(name);
    path = made ? made : "/tmp";
  }
  ~ScratchFolder() {
    std::error_code ec;
    if (path != "/tmp") std::filesystem::remove_all(path, ec);
  }
};

/// The command line's values.
struct IdentifyArgs {
  std::vector<std::string> data_files, overrides, free, candidates;
  std::string config, out_dir = "out/identify";
  int jobs = flagella::defaultJobs();
  bool quiet = false, no_plot = false, calibrate_only = false, sequential_fits = false;
};

/// Declares the command-line options, bound to `a`.
void addOptions(CLI::App& app, IdentifyArgs& a) {
  app.add_option("--data", a.data_files,
                 "measured data: metadata YAML (steady_state or time_series; CSV or bag), "
                 "repeatable")
      ->required();
  app.add_option("--config", a.config,
                 "baseline robot config (YAML), e.g. config/granular_design1.yaml")
      ->required();
  app.add_option("--free", a.free,
                 "baseline config fields to fit (default: medium.viscosity, "
                 "effects.stokes_head.C_t, effects.stokes_head.C_r where present; on a "
                 "single-flagellum robot C_t and C_r only)")
      ->delimiter(',');
  app.add_option("--candidates", a.candidates, "candidate effects to consider (default: all)")
      ->delimiter(',');
  app.add_option("--set", a.overrides,
                 "override a baseline config field, e.g. robot.tail_edges=8 (repeatable)");
  app.add_option("--out", a.out_dir, "report directory")->capture_default_str();
  app.add_option("--jobs", a.jobs, "simulations run in parallel")
      ->check(CLI::Range(1, flagella::kMaxJobs))
      ->capture_default_str();
  app.add_flag("--calibrate-only", a.calibrate_only,
               "only fit the free parameters on every experiment (no held-out split, no "
               "candidates): writes calibration.json, calibration.md, calibrated_config.yaml");
  app.add_flag("--no-plot", a.no_plot, "do not draw report.png");
  app.add_flag("--quiet", a.quiet, "no progress output");
  app.add_flag("--sequential-fits", a.sequential_fits,
               "fit the candidates one at a time (default with --jobs 2 or more: two at a time, "
               "same fits and verdict)");
}

/// Draws report.png with the plotting script; warns (the report stands without it) on failure.
void plotReport(const std::string& out_dir) {
  const std::string cmd =
      "python3 " FLAGELLA_SCRIPTS_DIR "/plot_identification.py '" + out_dir + "'";
  if (std::system(cmd.c_str()) != 0)
    std::cerr << "warning: plotting failed (" << cmd << "); the report is complete without it\n";
}

/// The whole identification: fit, diagnose, select, report; prints the verdict and the files.
int runIdentification(const IdentifyArgs& a, MeasuredData data, const YAML::Node& baseline,
                      const std::function<void(const std::string&)>& progress,
                      const std::string& command_line) {
  IdentifyOptions options;
  options.free = a.free.empty() ? defaultFree(baseline) : a.free;
  options.candidates = a.candidates;
  options.evaluator.jobs = a.jobs;
  options.concurrent_fits = !a.sequential_fits;
  options.progress = progress;
  options.fit.progress = progress;
  progress("read " + std::to_string(data.tables.size()) + " table(s) and " +
           std::to_string(data.series.size()) + " time series; fitting " +
           std::to_string(options.free.size()) + " baseline parameters");
  Identification identification(std::move(data), baseline, a.config, options);
  const IdentifyResult result = identification.run();
  ReportInputs inputs;
  inputs.data_files = a.data_files;
  inputs.baseline_config = a.config;
  inputs.command_line = command_line;
  const std::vector<std::string> files = writeReport(identification, result, inputs, a.out_dir);
  if (!a.no_plot) plotReport(a.out_dir);
  std::cout << "\nverdict: " << verdictText(result.verdict) << "\n" << result.summary << "\n";
  for (const std::string& f : files) std::cout << "wrote " << f << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "flagella_identify: calibrate a robot config on measured data, diagnose what it gets "
      "wrong, name the physical effect that explains it, and report the held-out gain"};
  IdentifyArgs a;
  addOptions(app, a);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  // Under mpirun every rank runs the same fit, its model runs spread over the ranks
  // (distributed_for.h); rank 0 reports, the others write into a scratch folder, removed at exit.
  const flagella::MpiScope mpi;
  std::unique_ptr<ScratchFolder> scratch;
  if (!flagella::isRootRank()) {
    scratch = std::make_unique<ScratchFolder>();
    a.out_dir = scratch->path;
    a.quiet = a.no_plot = true;
    if (!std::freopen("/dev/null", "w", stdout)) a.quiet = true;  // rank 0 prints the report
  }

  const auto start = std::chrono::steady_clock::now();
  auto progress = [&](const std::string& line) {
    if (a.quiet) return;
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "[" << std::fixed << std::setprecision(1) << s << " s] " << line << std::endl;
  };
  return flagella::cli::runGuarded([&] {
    enableBagInput();
    MeasuredData data = readMeasuredData(a.data_files);
    const YAML::Node baseline = loadConfigTree(a.config, a.overrides);
    for (const std::string& name : a.candidates) candidateByName(name);  // validates the names
    if (a.calibrate_only) {
      CalibrationOptions c;
      c.free = a.free.empty() ? defaultFree(baseline) : a.free;
      c.evaluator.jobs = a.jobs;
      c.progress = progress;
      c.fit.progress = progress;
      runCalibration(data, baseline, a.config, a.data_files, c, a.out_dir);
      return 0;
    }
    std::string command_line;
    for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
    return runIdentification(a, std::move(data), baseline, progress, command_line);
  });
}
