#include "run_commands.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "flagella_sim/beam/euler_bernoulli_beam.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/outputs/output_writers.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/exact_json.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/progress_printer.h"
#include "flagella_sim/simulation/problem_size.h"
#include "flagella_sim/simulation/simulation.h"
#include "plot_command.h"
#include "summary_json.h"

namespace flagella::cli {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// "n = 2" for a multi-tail robot, "helical, 3.5 pitches" for the helical one.
std::string robotLabel(const SimulationConfig& c) {
  if (!c.isHelical()) return "n = " + std::to_string(c.geometry.n_tails);
  char buf[64];
  std::snprintf(buf, sizeof(buf), "helical, %g pitches", c.helical.pitch_count);
  return buf;
}

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
                c.source.c_str(), robotLabel(c).c_str(), units::radPerSecToRpm(c.motor.omega),
                m.window_start, m.window_end, units::radPerSecToRpm(m.omega_h), m.omega_h,
                units::radPerSecToRpm(m.omega_t), m.omega_t, units::metresToMm(m.speed), m.yaw_rate,
                circleText(m).c_str(),
                m.efficiency_valid ? std::to_string(m.efficiency).c_str() : "n/a",
                m.newton_iterations, m.subdivided_steps);
  out << buf;
  if (c.isHelical())  // docs/model.md 8.4.4
    out << "  heading change = " << units::radToDeg(m.heading_change)
        << " deg, flagellum tilt max = " << units::radToDeg(m.flagellum_tilt_max) << " deg ("
        << (m.buckled ? "buckled" : "not buckled") << ", threshold " << c.buckling_tilt_deg
        << " deg)\n";
}

struct RunResult {
  SummaryMetrics summary;
  double wall = 0.0;
  bool failed = false;
  std::string error;
};

// A sweep case's result as text, for the ranks of an MPI run (distributed_for.h): the fields the
// sweep table and its progress lines use, doubles exactly (exact_json.h).

std::string encodeResult(const RunResult& r) {
  const SummaryMetrics& m = r.summary;
  return nlohmann::json{{"failed", r.failed},
                        {"error", r.error},
                        {"wall", r.wall},
                        {"speed", exactJson(m.speed)},
                        {"omega_h", exactJson(m.omega_h)},
                        {"omega_t", exactJson(m.omega_t)},
                        {"yaw_rate", exactJson(m.yaw_rate)},
                        {"efficiency_valid", m.efficiency_valid},
                        {"efficiency", exactJson(m.efficiency)},
                        {"flagellum_tilt_max", exactJson(m.flagellum_tilt_max)},
                        {"buckled", m.buckled}}
      .dump();
}

RunResult decodeResult(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  RunResult r;
  r.failed = j.at("failed").get<bool>();
  r.error = j.at("error").get<std::string>();
  r.wall = j.at("wall").get<double>();
  SummaryMetrics& m = r.summary;
  m.speed = exactNumber(j.at("speed"));
  m.omega_h = exactNumber(j.at("omega_h"));
  m.omega_t = exactNumber(j.at("omega_t"));
  m.yaw_rate = exactNumber(j.at("yaw_rate"));
  m.efficiency_valid = j.at("efficiency_valid").get<bool>();
  m.efficiency = exactNumber(j.at("efficiency"));
  m.flagellum_tilt_max = exactNumber(j.at("flagellum_tilt_max"));
  m.buckled = j.at("buckled").get<bool>();
  return r;
}

RunResult simulate(const SimulationConfig& config, Simulation& sim, bool quiet) {
  RunResult r;
  ProgressPrinter progress(config.duration, quiet);
  const Clock::time_point t0 = Clock::now();
  try {
    sim.run(config.duration, std::ref(progress));
  } catch (const SolverFailure& e) {
    r.failed = true;
    r.error = e.what();
  }
  r.wall = secondsSince(t0);
  r.summary = sim.summary();
  return r;
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

int sweepCommand(const SweepOptions& o) {
  requireJobs("--jobs", o.jobs);
  struct Case {
    int n;
    double rpm;
    SimulationConfig config;
    RunResult result;
  };
  std::vector<Case> cases;
  // Every case is loaded (and validated) before any runs, so bad input fails fast with exit 2.
  // Without --n-tails the config's own robot is swept (the helical robot has one flagellum).
  const std::vector<int> tails = o.n_tails.empty() ? std::vector<int>{0} : o.n_tails;
  for (int n : tails)
    for (double rpm : o.omega_rpm) {
      std::vector<std::string> overrides = o.overrides;
      if (n > 0) overrides.push_back("robot.n_tails=" + std::to_string(n));
      std::ostringstream omega;
      omega << std::setprecision(17) << rpm;
      overrides.push_back("motor.omega_rpm=" + omega.str());
      SimulationConfig config = loadSimulationConfig(o.config, overrides);
      const int count = config.isHelical() ? 1 : config.geometry.n_tails;
      cases.push_back({count, rpm, std::move(config), {}});
    }
  std::filesystem::create_directories(o.out_dir);
  std::mutex mutex;
  size_t done = 0;
  // On this rank's threads, or spread over mpirun's ranks (every rank gets every result).
  const std::vector<std::string> results =
      distributedFor(static_cast<int>(cases.size()), o.jobs, [&](int i) {
        RunResult r;
        try {
          Simulation sim(cases[i].config);
          r = simulate(cases[i].config, sim, true);
        } catch (const std::exception& e) {  // never let an exception escape a worker thread
          r.failed = true;
          r.error = e.what();
        }
        std::lock_guard<std::mutex> lock(mutex);
        ++done;
        if (!o.quiet)
          std::fprintf(stderr,
                       "[%zu/%zu%s] n = %d, omega_T = %g rpm: v = %.4f mm/s, omega_h = %.2f rpm "
                       "(%.1f s)%s\n",
                       done, cases.size(),
                       mpiSize() > 1 ? (" on rank " + std::to_string(mpiRank())).c_str() : "",
                       cases[i].n, cases[i].rpm, units::metresToMm(r.summary.speed),
                       units::radPerSecToRpm(r.summary.omega_h), r.wall,
                       r.failed ? " SOLVER FAILURE" : "");
        return encodeResult(r);
      });
  for (std::size_t i = 0; i < cases.size(); ++i) cases[i].result = decodeResult(results[i]);
  int status = 0;
  for (const Case& c : cases)
    if (c.result.failed) status = 3;
  if (!isRootRank()) return status;  // rank 0 writes the table

  const std::string table = o.out_dir + "/sweep.csv";
  std::ofstream out(table);
  out << "n_tails,omega_T_rpm,omega_h_rpm,omega_t_rpm,speed_mm_s,yaw_rate_rad_s,efficiency,solver_"
         "failure,flagellum_tilt_max_deg,buckled\n";
  for (const Case& c : cases) {
    const SummaryMetrics& m = c.result.summary;
    out << c.n << "," << c.rpm << "," << units::radPerSecToRpm(m.omega_h) << ","
        << units::radPerSecToRpm(m.omega_t) << "," << units::metresToMm(m.speed) << ","
        << m.yaw_rate << "," << (m.efficiency_valid ? std::to_string(m.efficiency) : "") << ","
        << (c.result.failed ? 1 : 0) << ","
        << (c.config.isHelical() ? std::to_string(units::radToDeg(m.flagellum_tilt_max)) : "")
        << "," << (c.config.isHelical() ? (m.buckled ? "1" : "0") : "") << "\n";
  }
  out.close();
  std::printf("sweep table: %s\n", table.c_str());
  flagella::cli::plotTable(o.plot_script, table, o.out_dir + "/sweep.png");
  for (const Case& c : cases)
    if (c.result.failed)
      std::fprintf(stderr, "error: n = %d, omega_T = %g rpm: %s\n", c.n, c.rpm,
                   c.result.error.c_str());
  return status;
}

int beamCommand(const BeamOptions& o) {
  const SimulationConfig c = loadSimulationConfig(o.config, o.overrides);
  if (c.isHelical())
    throw ConfigError(o.config +
                      ": robot.type helical: the beam model (docs/model.md 6) is for "
                      "the multi-tail robots");
  beam::BeamDesign d;
  d.n_tails = c.geometry.n_tails;
  d.tail_length = c.geometry.tail_length;
  d.tail_radius = c.geometry.tail_material.radius;
  d.youngs_modulus = c.geometry.tail_material.youngs_modulus;
  d.disc_radius = c.geometry.disc_radius;
  d.head_radius = c.head_radius;
  d.viscosity = c.medium.viscosity();
  d.log_form = RftLogForm::kTwoLengthOverRadius;
  // The beam model uses the same (validated) effect parameters as the rod model.
  const Simulation probe(c);
  d.C_t = probe.parameter("effects.stokes_head.C_t");
  d.C_r = probe.parameter("effects.stokes_head.C_r");
  d.head_radius = probe.parameter("effects.stokes_head.head_radius");
  for (const EffectSpec& e : c.effects)
    if (e.name == "rft") d.log_form = parseRftLogForm(e.option("log_form"));
  const double omega = std::abs(c.motor.omega);
  std::vector<beam::BeamRegime> regimes;
  if (o.regime == "LB" || o.regime == "all") regimes.push_back(beam::BeamRegime::kLinear);
  if (o.regime == "NLB" || o.regime == "all") regimes.push_back(beam::BeamRegime::kNonlinear);
  if (o.regime == "NLB-no-head" || o.regime == "all")
    regimes.push_back(beam::BeamRegime::kNonlinearWithoutHead);
  std::printf("beam model (docs/model.md 6), %s, n = %d, omega_T = %.3f rpm\n", o.config.c_str(),
              d.n_tails, units::radPerSecToRpm(omega));
  std::printf("%-14s %12s %12s %14s %12s %14s\n", "model", "omega_h rpm", "omega_t rpm", "v mm/s",
              "w(L)/L", "F_p/tail N");
  for (beam::BeamRegime regime : regimes) {
    const beam::BeamSolution s = beam::solveBeamModel(d, omega, regime);
    std::printf("%-14s %12.5f %12.5f %14.6g %12.5f %14.6g%s\n", beam::toString(regime).c_str(),
                units::radPerSecToRpm(s.omega_h), units::radPerSecToRpm(s.omega_t),
                units::metresToMm(s.speed), s.relative_tip_deflection, s.propulsive_force,
                s.converged ? "" : "  (not converged)");
  }
  if (o.compare_rod) {
    Simulation sim(c);
    const RunResult r = simulate(c, sim, o.quiet);
    const SummaryMetrics& m = r.summary;
    const double propulsive =
        d.C_t * 6.0 * M_PI * d.viscosity * d.head_radius * m.speed / d.n_tails;
    std::printf("%-14s %12.5f %12.5f %14.6g %12s %14.6g\n", "rod (DER)",
                units::radPerSecToRpm(m.omega_h), units::radPerSecToRpm(m.omega_t),
                units::metresToMm(m.speed), "-", propulsive);
    if (r.failed) return 3;
  }
  return 0;
}

int paramsCommand(const CommonOptions& o) {
  const SimulationConfig c = loadSimulationConfig(o.config, o.overrides);
  Simulation sim(c);
  std::printf("%-45s %14s %14s %14s  %s\n", "parameter", "value", "min", "max", "unit");
  for (const std::string& name : sim.parameterNames()) {
    const ParameterSpec& p = sim.parameterSpec(name);
    std::printf("%-45s %14.6g %14.6g %14.6g  %s\n", name.c_str(), p.value, p.min, p.max,
                p.unit.c_str());
  }
  return 0;
}

int effectsCommand(bool markdown) {
  if (markdown) {
    std::cout << effectTableMarkdown();
    return 0;
  }
  for (const EffectDescriptor* d : effectRegistry()) {
    std::printf("%s: %s\n", d->name.c_str(), d->description.c_str());
    for (const EffectOption& o : d->options) {
      std::printf("  option    %-22s one of: %s (default %s)\n", o.name.c_str(),
                  o.choiceList().c_str(), o.fallback.c_str());
    }
    for (const ParameterSpec& p : d->parameters) {
      const std::string rule = d->defaultRule(p.name);
      std::printf("  parameter %-22s [%g, %g] %s, default %s: %s\n", p.name.c_str(), p.min, p.max,
                  p.unit.c_str(), rule.empty() ? std::to_string(p.value).c_str() : rule.c_str(),
                  p.description.c_str());
    }
    if (d->discovery)
      for (const FittableParameter& v : d->discovery->variables)
        std::printf("  discovery %-22s fitted in [%g, %g] %s%s\n", v.variable.c_str(), v.lower,
                    v.upper, v.unit.c_str(), v.log_scale ? " (log scale)" : "");
  }
  return 0;
}

}  // namespace flagella::cli
