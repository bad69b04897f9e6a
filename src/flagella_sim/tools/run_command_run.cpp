// flagella_run run: one simulation, its outputs staged and published, its summary printed.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>

#include "flagella_sim/core/units.h"
#include "flagella_sim/outputs/output_writers.h"
#include "flagella_sim/simulation/problem_size.h"
#include "flagella_sim/simulation/simulation.h"
#include "plot_command.h"
#include "run_command_shared.h"
#include "run_commands.h"
#include "summary_json.h"

namespace flagella::cli {

namespace {

// The circle radius, or why there is none: a path that turned by less than kMinCircleTurn over
// the steady window is nearly straight, and a fitted radius of kilometres says nothing.
std::string circleText(const SummaryMetrics& m) {
  constexpr double kMinCircleTurn = 0.1;  // [rad], 5.7 deg
  if (!m.circle_valid) return "n/a";
  const double turned = std::abs(m.yaw_rate) * (m.window_end - m.window_start);
  if (turned < kMinCircleTurn) {
    char buf[128];
    std::snprintf(buf, sizeof(buf), "n/a (path nearly straight: turned %.2f deg in the window)",
                  units::radToDeg(turned));
    return buf;
  }
  return std::to_string(units::metresToMm(m.circle_radius)) + " mm";
}

void printSummary(const SimulationConfig& c, const SummaryMetrics& m, std::ostream& out) {
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
                "summary (%s, %s, omega_T = %.2f rpm, steady window %.1f-%.1f s)\n"
                "  omega_h = %.4f rpm (%.5f rad/s)\n"
                "  omega_t = %.4f rpm (%.5f rad/s)\n"
                "  v       = %.5f mm/s (forward, along the initial head axis)\n"
                "  yaw rate = %.5f rad/s, circle radius = %s\n"
                "  efficiency = %s\n"
                "  Newton iterations = %ld, subdivided steps = %ld\n",
                c.source.c_str(), c.robot->label().c_str(), units::radPerSecToRpm(c.motor.omega),
                m.window_start, m.window_end, units::radPerSecToRpm(m.omega_h), m.omega_h,
                units::radPerSecToRpm(m.omega_t), m.omega_t, units::metresToMm(m.speed), m.yaw_rate,
                circleText(m).c_str(),
                m.efficiency_valid ? std::to_string(m.efficiency).c_str() : "n/a",
                m.newton_iterations, m.subdivided_steps);
  out << buf;
  if (c.robot->hasFlagellumTilt())  // docs/model.md 8.4.4
    out << "  heading change = " << units::radToDeg(m.heading_change)
        << " deg, flagellum tilt max = " << units::radToDeg(m.flagellum_tilt_max) << " deg ("
        << (m.buckled ? "buckled" : "not buckled") << ", threshold " << c.buckling_tilt_deg
        << " deg)\n";
}

// The files `run` writes into its output folder.
constexpr char kTimeseriesFile[] = "timeseries.csv";
constexpr char kNodesFile[] = "nodes.csv";
constexpr char kSummaryFile[] = "summary.json";
constexpr char kPlotFile[] = "run.png";

// The run's outputs are written into a staging folder inside the output folder and moved over
// the previous run's files only when the run has ended (also by a solver failure, whose outputs
// hold the run up to it): an interrupted or refused run leaves the previous outputs as they were.
constexpr char kStagingFolder[] = ".run.partial";

/// Removes the staging folder when the run ends, its outputs moved or not (an exception).
class StagingGuard {
 public:
  explicit StagingGuard(std::filesystem::path path) : path_(std::move(path)) {}
  ~StagingGuard() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  StagingGuard(const StagingGuard&) = delete;
  StagingGuard& operator=(const StagingGuard&) = delete;

 private:
  std::filesystem::path path_;
};

/// Moves the staged outputs into `out_dir`, replacing the previous run's (said on stderr) and
/// removing those this run did not write (nodes.csv of an earlier --nodes run, a plot that
/// failed), so nothing stale is left beside them.
void publishRun(const std::filesystem::path& staging, const std::filesystem::path& out_dir) {
  std::string replaced;
  for (const char* name : {kTimeseriesFile, kNodesFile, kSummaryFile, kPlotFile}) {
    const std::filesystem::path target = out_dir / name;
    if (std::filesystem::exists(target))
      replaced += (replaced.empty() ? "" : ", ") + std::string(name);
    if (std::filesystem::exists(staging / name))
      std::filesystem::rename(staging / name, target);  // atomic per file
    else
      std::filesystem::remove(target);
  }
  if (!replaced.empty())
    std::fprintf(stderr, "replaced the previous run in %s/ (%s)\n", out_dir.c_str(),
                 replaced.c_str());
}

}  // namespace

int runCommand(const RunOptions& o) {
  const SimulationConfig config = loadSimulationConfig(o.config, o.overrides);
  const std::filesystem::path staging = std::filesystem::path(o.out_dir) / kStagingFolder;
  std::filesystem::remove_all(staging);  // left by an interrupted run
  std::filesystem::create_directories(staging);
  const std::string staged = staging.string() + "/";
  StagingGuard staging_guard(staging);
  const std::string size = describeProblemSize(estimateProblemSize(config));
  if (!o.quiet && !size.empty()) std::fprintf(stderr, "size (estimate): %s\n", size.c_str());
  Simulation sim(config);
  sim.setRecordNodes(o.nodes);
  if (!o.quiet)
    std::fprintf(stderr, "running %s: %d nodes, %d DOFs, dt = %g s, %g s simulated\n",
                 o.config.c_str(), sim.network().numNodes(), sim.network().ndof(), config.dt,
                 config.duration);
  const RunResult r = simulate(config, sim, o.quiet);
  writeTrajectoryCsv(staged + kTimeseriesFile, sim.trajectory());
  if (o.nodes) writeNodesCsv(staged + kNodesFile, sim.trajectory());
  writeText(staged + kSummaryFile, summaryJson(config, r.summary, r.wall));
  printSummary(config, r.summary, std::cout);
  std::printf("  wall time %.2f s, %.1fx real time; outputs in %s/\n", r.wall,
              r.wall > 0 ? sim.time() / r.wall : 0.0, o.out_dir.c_str());
  std::fflush(stdout);
  plotTable(o.plot_script, staged + kTimeseriesFile, staged + kPlotFile, "plot",
            o.out_dir + "/" + kPlotFile);
  publishRun(staging, o.out_dir);
  if (r.failed) {
    std::fprintf(stderr, "error: solver failure, outputs hold the run up to t = %.3f s: %s\n",
                 sim.time(), r.error.c_str());
    return 3;
  }
  return 0;
}

}  // namespace flagella::cli
