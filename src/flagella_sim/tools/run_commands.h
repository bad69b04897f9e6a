// The subcommands of flagella_run, separated from command-line parsing.
#pragma once

#include <string>
#include <vector>

namespace flagella::cli {

struct CommonOptions {
  std::string config;
  std::vector<std::string> overrides;  ///< "section.field=value"
  std::string out_dir = "out";
  bool quiet = false;
};

struct RunOptions : CommonOptions {
  bool nodes = false;       ///< also write node positions
  std::string plot_script;  ///< draws run.png from timeseries.csv; "" = no plot
};

struct SweepOptions : CommonOptions {
  std::vector<double> omega_rpm;
  std::vector<int> n_tails;
  int jobs = 2;
  std::string plot_script;
};

struct BeamOptions : CommonOptions {
  std::string regime = "all";  ///< LB | NLB | NLB-no-head | all
  bool compare_rod = false;
};

int runCommand(const RunOptions& o);
int sweepCommand(const SweepOptions& o);
int beamCommand(const BeamOptions& o);
int paramsCommand(const CommonOptions& o);
/// Lists every registered effect (options, parameters, discovery variables); `markdown`: the
/// README's effect table.
int effectsCommand(bool markdown);
/// flagella_run robots: every robot type a config can name (robot.type) with its fields.
int robotsCommand(bool markdown);

}  // namespace flagella::cli
