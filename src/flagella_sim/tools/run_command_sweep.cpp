// flagella_run sweep: a grid of motor speeds and tail counts, run in parallel, into sweep.csv.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/exact_json.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/simulation/simulation.h"
#include "plot_command.h"
#include "run_command_shared.h"
#include "run_commands.h"

namespace flagella::cli {

namespace {

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

}  // namespace

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
      const int count = config.robot->tailCount();
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
        << (c.config.robot->hasFlagellumTilt()
                ? std::to_string(units::radToDeg(m.flagellum_tilt_max))
                : "")
        << "," << (c.config.robot->hasFlagellumTilt() ? (m.buckled ? "1" : "0") : "") << "\n";
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

}  // namespace flagella::cli
