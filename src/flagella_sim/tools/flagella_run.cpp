// flagella_run: headless runner of the rod-network simulator (run, sweep, beam, params, effects,
// robots).
#include <CLI/CLI.hpp>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/runtime/tool_main.h"
#include "flagella_sim/solver/implicit_stepper.h"
#include "run_commands.h"

using namespace flagella::cli;

namespace {

void addCommon(CLI::App* app, CommonOptions& o) {
  // Existence is checked by the config loader so that a missing file is an input error (exit 2).
  app->add_option("config", o.config, "robot/run config (YAML), e.g. config/granular_design1.yaml")
      ->required();
  app->add_option("--set", o.overrides,
                  "override a config field: section.field=value (repeatable)");
  app->add_option("--out", o.out_dir, "output directory")->capture_default_str();
  app->add_flag("--quiet", o.quiet, "no progress output");
}

// Full precision: std::to_string would round 5e-7 to 0.000000.
std::string exact(double x) {
  std::ostringstream out;
  out << std::setprecision(17) << x;
  return out.str();
}

// Convenience flags that become overrides.
struct Shortcuts {
  double omega_rpm = 0, tail_length = 0, dt = 0, duration = 0;
  int n_tails = 0;
  void add(CLI::App* app, bool with_n = true, bool with_omega = true) {
    if (with_omega) app->add_option("--omega-rpm", omega_rpm, "motor speed omega_T [rpm]");
    if (with_n) app->add_option("--n-tails", n_tails, "number of tails");
    app->add_option("--tail-length", tail_length, "tail length [m]");
    app->add_option("--dt", dt, "time step [s]");
    app->add_option("--duration", duration, "simulated time [s]");
  }
  void apply(CLI::App* app, std::vector<std::string>& ov) const {
    auto given = [&](const char* name) {
      return app->get_option_no_throw(name) && app->count(name) > 0;
    };
    if (given("--omega-rpm")) ov.push_back("motor.omega_rpm=" + exact(omega_rpm));
    if (given("--n-tails")) ov.push_back("robot.n_tails=" + std::to_string(n_tails));
    if (given("--tail-length")) ov.push_back("robot.tail_length=" + exact(tail_length));
    if (given("--dt")) ov.push_back("simulation.dt=" + exact(dt));
    if (given("--duration")) ov.push_back("simulation.duration=" + exact(duration));
  }
};

// The sweep subcommand and its options.
CLI::App* addSweep(CLI::App& app, SweepOptions& sweep, Shortcuts& shortcuts) {
  CLI::App* cmd = app.add_subcommand("sweep", "sweep omega_T and n; write sweep.csv and sweep.png");
  addCommon(cmd, sweep);
  shortcuts.add(cmd, false, false);
  cmd->add_option("--omega-rpm", sweep.omega_rpm, "motor speeds [rpm]")->delimiter(',')->required();
  cmd->add_option("--n-tails", sweep.n_tails,
                  "tail counts (multi-tail robots; default: the config's, one line)")
      ->delimiter(',');
  sweep.jobs = flagella::defaultJobs();
  cmd->add_option("--jobs", sweep.jobs, "parallel runs, in [1, 256] (default: the core count)")
      ->capture_default_str();
  sweep.plot_script = FLAGELLA_PLOT_SCRIPT;
  cmd->add_option("--plot-script", sweep.plot_script, "matplotlib plot script ('' to skip)")
      ->capture_default_str();
  return cmd;
}

// A listing subcommand (effects, robots) with its --markdown flag.
CLI::App* addListing(CLI::App& app, const char* name, const char* what, const char* markdown_help,
                     bool& markdown) {
  CLI::App* cmd = app.add_subcommand(name, what);
  cmd->add_flag("--markdown", markdown, markdown_help);
  return cmd;
}

}  // namespace

int main(int argc, char** argv) {
  const flagella::MpiScope mpi;  // under mpirun: `sweep` spreads its runs over the ranks
  CLI::App app{"flagella_run: simulate soft flagellated robots (discrete elastic rod networks)"};
  app.require_subcommand(1);

  RunOptions run;
  Shortcuts run_short;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "simulate one config; write timeseries.csv, summary.json and run.png");
  addCommon(run_cmd, run);
  run_short.add(run_cmd);
  run_cmd->add_flag("--nodes", run.nodes, "also write all node positions to nodes.csv");
  run.plot_script = FLAGELLA_RUN_PLOT_SCRIPT;
  run_cmd->add_option("--plot-script", run.plot_script,
                      "matplotlib script drawing run.png (head path, speed, yaw rate); '' to skip");

  SweepOptions sweep;
  Shortcuts sweep_short;
  CLI::App* sweep_cmd = addSweep(app, sweep, sweep_short);

  BeamOptions beam;
  Shortcuts beam_short;
  CLI::App* beam_cmd = app.add_subcommand(
      "beam", "Euler-Bernoulli beam model (docs/model.md 6) for a config's design");
  addCommon(beam_cmd, beam);
  beam_short.add(beam_cmd);
  beam_cmd->add_option("--regime", beam.regime, "LB | NLB | NLB-no-head | all")
      ->check(CLI::IsMember({"LB", "NLB", "NLB-no-head", "all"}))
      ->capture_default_str();
  beam_cmd->add_flag("--compare-rod", beam.compare_rod,
                     "also run the rod model on the same design");

  CommonOptions params;
  CLI::App* params_cmd = app.add_subcommand("params", "list the named parameters of a config");
  addCommon(params_cmd, params);

  bool effects_markdown = false, robots_markdown = false;
  CLI::App* effects_cmd =
      addListing(app, "effects", "list every effect a config can switch on, with its schema",
                 "print the README's effect table", effects_markdown);
  CLI::App* robots_cmd =
      addListing(app, "robots", "list every robot type a config can name, with its fields",
                 "print the README's robot tables", robots_markdown);

  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    if (*run_cmd) {
      run_short.apply(run_cmd, run.overrides);
      return runCommand(run);
    }
    if (*sweep_cmd) {
      sweep_short.apply(sweep_cmd, sweep.overrides);
      return sweepCommand(sweep);
    }
    if (*beam_cmd) {
      beam_short.apply(beam_cmd, beam.overrides);
      return beamCommand(beam);
    }
    if (*params_cmd) return paramsCommand(params);
    if (*effects_cmd) return effectsCommand(effects_markdown);
    if (*robots_cmd) return robotsCommand(robots_markdown);
    return 0;
  });
}
