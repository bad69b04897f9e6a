// flagella_sweep: runs a sweep file's points (tool runs over a grid or list of config settings)
// on a local process pool, under MPI, or as a Slurm array, and builds one result table.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sweep/backends.h"
#include "flagella_sweep/point_runner.h"
#include "flagella_sweep/sweep_spec.h"
#include "flagella_sweep/sweep_store.h"

namespace {

using namespace flagella::sweep;
namespace fs = std::filesystem;

struct Options {
  std::string sweep, out, backend = "local";
  int jobs = flagella::defaultJobs();
  int index = -1;
  bool plot = false, quiet = false;
  std::vector<std::string> plot_keys, sbatch;
  int max_running = 0;
};

std::string defaultOut(const std::string& sweep) {
  return "sweep_out/" + fs::path(sweep).stem().string();
}

/// Builds the table (and the plot); returns the exit status: 0, or 3 with failed points.
int finish(const SweepSpec& spec, const SweepStore& store, const Options& o) {
  std::vector<int> failed;
  const int rows = store.writeTable(spec, failed);
  const int total = static_cast<int>(spec.points.size());
  std::printf("table: %s/results.csv and results.json (%d of %d points, %zu failed)\n",
              store.directory().c_str(), rows, total, failed.size());
  std::fflush(stdout);
  // The plot's axes: the parameters that take more than one value.
  std::vector<std::string> varying;
  for (const std::string& p : spec.parameters) {
    std::set<std::string> values;
    for (const PointSettings& point : spec.points)
      for (const auto& [field, value] : point)
        if (field == p) values.insert(value);
    if (values.size() > 1) varying.push_back(p);
  }
  if (o.plot) {
    if (varying.empty() || varying.size() > 2) {
      std::fprintf(stderr,
                   "warning: --plot draws sweeps of one or two varying parameters, this one has "
                   "%zu\n",
                   varying.size());
    } else {
      std::string cmd = "/usr/bin/python3 '" FLAGELLA_SWEEP_PLOT_SCRIPT "' '" + store.directory() +
                        "/results.csv' '" + store.directory() + "/results.png'";
      for (const std::string& p : varying) cmd += " --param '" + p + "'";
      for (const std::string& p : spec.parameters)
        if (std::find(varying.begin(), varying.end(), p) == varying.end())
          cmd += " --fixed '" + p + "'";
      for (const std::string& k : o.plot_keys) cmd += " --key '" + k + "'";
      if (std::system(cmd.c_str()) == 0)
        std::printf("plot: %s/results.png\n", store.directory().c_str());
      else
        std::fprintf(stderr, "warning: plotting failed (%s)\n", cmd.c_str());
    }
  }
  std::fflush(stdout);
  for (int i : failed)
    std::fprintf(stderr, "failed point %d: %s\n", i,
                 store.readRecord(i)["error"].get<std::string>().c_str());
  if (rows < total) {
    std::fprintf(stderr, "%d points have no result yet (run the sweep again to run them)\n",
                 total - rows);
    return 4;
  }
  return failed.empty() ? 0 : 3;
}

void printReport(const RunReport& r, const std::string& backend) {
  if (r.ran == 0) {
    std::printf("sweep: all %d points were already done\n", r.total);
    return;
  }
  // Utilisation: the share of the workers' time spent inside point processes (1 - idle and
  // bookkeeping). It is not the parallel efficiency, which compares with one worker
  // (scripts/bench_sweep.sh): on a loaded machine points run slower at full utilisation.
  const double utilisation = r.wall > 0 ? r.point_wall / (r.workers * r.wall) : 0.0;
  const double overhead = (r.wall * r.workers - r.point_wall) / r.ran;
  std::printf(
      "sweep (%s, %d workers): ran %d points (%d failed; %d already done) in %.2f s; point "
      "process %.3f s per point; runner time outside them %.1f ms per point; worker utilisation "
      "%.1f %%\n",
      backend.c_str(), r.workers, r.ran, r.failed, r.already, r.wall, r.point_wall / r.ran,
      1e3 * overhead, 100.0 * utilisation);
}

int runCommand(const Options& o) {
  const SweepSpec spec = loadSweepSpec(o.sweep);
  const SweepStore store(o.out.empty() ? defaultOut(o.sweep) : o.out);
  if (o.backend == "local") {
    flagella::requireJobs("--jobs", o.jobs);
    store.open(spec);
    printReport(runLocal(spec, store, o.jobs, o.quiet), "local");
    return finish(spec, store, o);
  }
  if (o.backend == "mpi") {
    if (!flagella::mpiCompiledIn())
      throw std::runtime_error(
          "this flagella_sweep was built without MPI (install libopenmpi-dev and rebuild)");
    int rank = 0;
    // Every rank checks the plan: a rank that cannot see the folder fails loudly.
    store.open(spec);
    const RunReport report = runMpi(spec, store, o.quiet, rank);
    if (rank != 0) return 0;
    printReport(report, "mpi");
    return finish(spec, store, o);
  }
  if (o.backend == "slurm") {
    store.open(spec);
    const std::vector<int> todo = store.missing(static_cast<int>(spec.points.size()));
    if (todo.empty()) {
      std::printf("sweep: all %zu points are done; building the table\n", spec.points.size());
      return finish(spec, store, o);
    }
    const std::string script = writeSlurmScript(spec, store, o.sbatch, o.max_running);
    std::printf(
        "slurm: %s runs %zu points (array %s)\nsubmit:  sbatch %s\nthen:    %s/flagella_sweep "
        "collect %s --out %s\n",
        script.c_str(), todo.size(), arrayRanges(todo).c_str(), script.c_str(),
        executableDirectory().c_str(), fs::absolute(o.sweep).string().c_str(),
        fs::absolute(store.directory()).string().c_str());
    return 0;
  }
  throw flagella::ConfigError("--backend must be local, mpi or slurm, got '" + o.backend + "'");
}

int runPointCommand(const Options& o) {
  const SweepSpec spec = loadSweepSpec(o.sweep);
  const int count = static_cast<int>(spec.points.size());
  if (o.index < 0 || o.index >= count)
    throw flagella::ConfigError("--index must be in [0, " + std::to_string(count - 1) + "], got " +
                                std::to_string(o.index));
  const SweepStore store(o.out.empty() ? defaultOut(o.sweep) : o.out);
  store.open(spec);
  const nlohmann::json record =
      runPoint(spec, o.index, executableDirectory(), store.workDirectory(o.index));
  store.writeRecord(record);
  std::printf("point %d: %s (%.2f s)%s%s\n", o.index, record["status"].get<std::string>().c_str(),
              record["wall_s"].get<double>(), record["error"] == "" ? "" : ": ",
              record["error"].get<std::string>().c_str());
  return record["status"] == "ok" ? 0 : 3;
}

int collectCommand(const Options& o) {
  const SweepSpec spec = loadSweepSpec(o.sweep);
  const SweepStore store(o.out.empty() ? defaultOut(o.sweep) : o.out);
  store.open(spec);
  return finish(spec, store, o);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "flagella_sweep: run a sweep file's points (local pool, MPI or Slurm) into one table"};
  app.require_subcommand(1);
  Options o;
  auto common = [&](CLI::App* c) {
    c->add_option("sweep", o.sweep, "sweep file (YAML), e.g. config/sweeps/helical_rate.yaml")
        ->required();
    c->add_option("--out", o.out, "output folder (default: sweep_out/<sweep file name>)");
  };
  CLI::App* run =
      app.add_subcommand("run", "run the points without a result, then build the table");
  common(run);
  run->add_option("--backend", o.backend,
                  "local (default), mpi (under mpirun) or slurm (writes an sbatch array script)")
      ->capture_default_str();
  run->add_option("--jobs", o.jobs, "local backend: points run at once, in [1, 256]")
      ->capture_default_str();
  run->add_option("--sbatch", o.sbatch,
                  "slurm backend: an extra #SBATCH line, e.g. --time=01:00:00 (repeatable)");
  run->add_option("--max-running", o.max_running,
                  "slurm backend: at most this many array tasks at once (0: no limit)");
  CLI::App* point =
      app.add_subcommand("run-point", "run one point and store its result (a Slurm array task)");
  common(point);
  point->add_option("--index", o.index, "the point's index")->required();
  CLI::App* collect = app.add_subcommand("collect", "build the table from the stored results");
  common(collect);
  for (CLI::App* c : {run, collect}) {
    c->add_flag("--plot", o.plot, "plot results.png for a sweep of one or two parameters");
    c->add_option("--plot-key", o.plot_keys,
                  "summary key to plot (repeatable; default: a few numeric ones)");
  }
  run->add_flag("--quiet", o.quiet, "no progress lines");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    if (run->parsed()) return runCommand(o);
    if (point->parsed()) return runPointCommand(o);
    return collectCommand(o);
  });
}
