// End-to-end tests of the flagella_run executable: subcommands, output files, exit codes
// (0 = ok, 1 = other error, 2 = config error, 3 = solver failure) and error messages.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "flagella_sim/outputs/output_writers.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr char kRunExe[] = FLAGELLA_RUN_EXE;
constexpr char kConfigDir[] = FLAGELLA_CONFIG_DIR;
constexpr char kDesign1[] = "granular_design1.yaml";
constexpr int kExitOk = 0;
constexpr int kExitOther = 1;
constexpr int kExitConfigError = 2;
constexpr int kExitSolverFailure = 3;
constexpr double kShortDuration = 2.0;   // [s] simulated in the short run
constexpr double kOutputInterval = 0.1;  // [s] output_interval of granular_design1.yaml
constexpr int kSweepRows = 2;            // 2 speeds x 1 tail count

std::string shippedConfig(const std::string& name) { return std::string(kConfigDir) + "/" + name; }

/// Single-quotes an argument for /bin/sh.
std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs flagella_run with `args` (already quoted where needed), capturing stdout + stderr.
CommandResult runTool(const std::string& args) {
  const std::string command = shellQuote(kRunExe) + " " + args + " 2>&1";
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) {
    ADD_FAILURE() << "popen failed for " << command;
    return result;
  }
  std::array<char, 4096> buffer;
  size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Lower-cased text holds no "nan" or "inf".
bool hasNonFinite(const std::string& text) {
  std::string lower = text;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return contains(lower, "nan") || contains(lower, "inf");
}

/// Value of a numeric key in a JSON text, found by string search ("key": value).
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string quoted = "\"" + key + "\":";
  const size_t at = json.find(quoted);
  if (at == std::string::npos) {
    ADD_FAILURE() << "key " << key << " missing in summary.json";
    return 0.0;
  }
  return std::stod(json.substr(at + quoted.size()));
}

class FlagellaRun : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kRunExe)) << kRunExe << " is not built (make flagella_run)";
  }
  const std::string design1_ = shellQuote(shippedConfig(kDesign1));
};

// ---------------------------------------------------------------------------------------------
// run
// ---------------------------------------------------------------------------------------------

TEST_F(FlagellaRun, ShortRunWritesTimeseriesAndSummary) {
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --duration 2 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  for (const char* key : {"omega_h", "omega_t"}) EXPECT_TRUE(contains(r.output, key)) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(\bv\s*=)"))) << r.output;
  EXPECT_FALSE(hasNonFinite(r.output)) << r.output;

  const fs::path csv = out.path() / "timeseries.csv";
  const fs::path json = out.path() / "summary.json";
  ASSERT_TRUE(fs::exists(csv));
  ASSERT_TRUE(fs::exists(json));
  // the run's plot (head path, speed, yaw rate) beside the table it was drawn from
  const fs::path png = out.path() / "run.png";
  ASSERT_TRUE(fs::exists(png)) << r.output;
  EXPECT_GT(fs::file_size(png), 10000u);
  EXPECT_TRUE(contains(r.output, "plot: ")) << r.output;

  const std::vector<std::string> rows = lines(testing::readTextFile(csv));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front(), trajectoryCsvHeader());
  const size_t columns = splitCsv(trajectoryCsvHeader()).size();
  const int expected_samples = static_cast<int>(std::lround(kShortDuration / kOutputInterval)) + 1;
  EXPECT_EQ(static_cast<int>(rows.size()) - 1, expected_samples);
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(splitCsv(rows[i]).size(), columns) << "row " << i << ": " << rows[i];
    EXPECT_FALSE(hasNonFinite(rows[i])) << "row " << i << ": " << rows[i];
  }
  EXPECT_NEAR(std::stod(splitCsv(rows.back())[0]), kShortDuration, 1e-6);

  const std::string summary = testing::readTextFile(json);
  EXPECT_FALSE(hasNonFinite(summary)) << summary;
  EXPECT_EQ(jsonNumber(summary, "n_tails"), 2.0);
  EXPECT_NEAR(jsonNumber(summary, "omega_T_rpm"), 100.0, 1e-9);
  EXPECT_NEAR(jsonNumber(summary, "duration_s"), kShortDuration, 1e-6);
  EXPECT_GT(jsonNumber(summary, "omega_h_rpm"), 0.0);
}

TEST_F(FlagellaRun, AStraightSwimmerPrintsNoCircleRadius) {
  // Three tails at 120 deg swim straight (symmetry): the least-squares circle of a straight path
  // has a radius of kilometres, which the summary does not print as a radius.
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --n-tails 3 --duration 2 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  EXPECT_TRUE(contains(r.output, "circle radius = n/a (path nearly straight")) << r.output;
}

TEST_F(FlagellaRun, ARunIntoTheSameFolderLeavesNoStaleFile) {
  // A run with --nodes, then one without into the same folder: the second says it replaces the
  // first and leaves no nodes.csv of the first behind.
  const TempDir out;
  const std::string args =
      "run " + design1_ + " --duration 0.2 --out " + shellQuote(out.path().string()) + " --quiet";
  ASSERT_EQ(runTool(args + " --nodes").exit_code, kExitOk);
  ASSERT_TRUE(fs::exists(out.path() / "nodes.csv"));
  const CommandResult second = runTool(args);
  ASSERT_EQ(second.exit_code, kExitOk) << second.output;
  EXPECT_TRUE(contains(second.output, "replaced the previous run")) << second.output;
  EXPECT_FALSE(fs::exists(out.path() / "nodes.csv"));
  EXPECT_TRUE(fs::exists(out.path() / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(out.path() / "summary.json"));
}

TEST_F(FlagellaRun, AnInterruptedRunLeavesThePreviousOutputs) {
  // A finished run, then one killed (SIGKILL) in the middle: the first run's files are there
  // byte for byte, and the next run clears the killed run's staging folder.
  const TempDir out;
  const std::string into = " --out " + shellQuote(out.path().string()) + " --quiet";
  ASSERT_EQ(runTool("run " + design1_ + " --duration 0.2" + into).exit_code, kExitOk);
  const std::string before = testing::readTextFile((out.path() / "timeseries.csv").string());
  const std::string summary = testing::readTextFile((out.path() / "summary.json").string());
  const std::string killed = "timeout -s KILL 2 " + shellQuote(kRunExe) + " run " + design1_ +
                             " --duration 100000" + into + " > /dev/null 2>&1";
  EXPECT_NE(std::system(killed.c_str()), 0);
  EXPECT_TRUE(fs::exists(out.path() / ".run.partial"));  // it was killed while running
  EXPECT_EQ(testing::readTextFile((out.path() / "timeseries.csv").string()), before);
  EXPECT_EQ(testing::readTextFile((out.path() / "summary.json").string()), summary);
  ASSERT_EQ(runTool("run " + design1_ + " --duration 0.1" + into).exit_code, kExitOk);
  EXPECT_FALSE(fs::exists(out.path() / ".run.partial"));
  EXPECT_NE(testing::readTextFile((out.path() / "timeseries.csv").string()), before);
}

TEST_F(FlagellaRun, AStepLongerThanTheOutputIntervalNamesTheStep) {
  // --dt 1 on a config whose output_interval is 0.1 s: the message names dt, which was set.
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --dt 1 --duration 1 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "must be at least simulation.dt (1 s)")) << r.output;
}

TEST_F(FlagellaRun, BadConfigExitsTwoNamingTheField) {
  const TempDir dir;
  const std::string config = dir.write("bad.yaml",
                                       "robot:\n"
                                       "  n_tails: 2\n"
                                       "  poisson_ratio: 0.7\n");
  const CommandResult r = runTool("run " + shellQuote(config) + " --out " +
                                  shellQuote(dir.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "robot.poisson_ratio")) << r.output;
  EXPECT_TRUE(contains(r.output, "[0, 0.5]")) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "timeseries.csv"));
}

TEST_F(FlagellaRun, UnknownFieldExitsTwo) {
  const TempDir dir;
  const std::string config = dir.write("typo.yaml", "robot:\n  n_tail: 2\n");
  const CommandResult r = runTool("run " + shellQuote(config) + " --out " +
                                  shellQuote(dir.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "robot.n_tail")) << r.output;
}

TEST_F(FlagellaRun, OutOfRangeOverrideExitsTwo) {
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --set robot.n_tails=0 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "robot.n_tails")) << r.output;
}

TEST_F(FlagellaRun, MalformedOverrideExitsTwo) {
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --set robot.n_tails --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "robot.n_tails")) << r.output;
}

TEST_F(FlagellaRun, EffectParameterOutOfRangeExitsTwo) {
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --set effects.stokes_head.C_t=-1 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "effects.stokes_head.C_t")) << r.output;
}

TEST_F(FlagellaRun, MissingConfigFileFailsWithAClearMessage) {
  const TempDir dir;
  const std::string missing = (dir.path() / "no_such_config.yaml").string();
  const CommandResult r =
      runTool("run " + shellQuote(missing) + " --out " + shellQuote(dir.path().string()));
  EXPECT_NE(r.exit_code, kExitOk) << r.output;
  EXPECT_TRUE(contains(r.output, missing)) << r.output;
  EXPECT_TRUE(contains(r.output, "does not exist") || contains(r.output, "cannot open"))
      << r.output;
}

// Small time steps given on the command line must reach the config unchanged (not rounded to
// six decimals).
TEST_F(FlagellaRun, SmallDtShortcutIsNotRounded) {
  const TempDir out;
  const CommandResult r = runTool("run " + design1_ + " --dt 5e-7 --duration 2e-6 --out " +
                                  shellQuote(out.path().string()) + " --quiet");
  EXPECT_EQ(r.exit_code, kExitOk) << r.output;
}

// ---------------------------------------------------------------------------------------------
// params, beam, sweep
// ---------------------------------------------------------------------------------------------

TEST_F(FlagellaRun, ParamsListsNamedParameters) {
  const CommandResult r = runTool("params " + design1_);
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  EXPECT_TRUE(contains(r.output, "medium.viscosity")) << r.output;
  EXPECT_TRUE(contains(r.output, "effects.stokes_head.C_t")) << r.output;
  EXPECT_TRUE(contains(r.output, "6.828")) << r.output;
}

TEST_F(FlagellaRun, ParamsRowsFillTheMinMaxColumns) {
  const CommandResult r = runTool("params " + design1_);
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  for (const std::string& line : lines(r.output)) {
    if (line.rfind("effects.stokes_head.C_t", 0) != 0) continue;
    std::stringstream ss(line);
    std::vector<std::string> cells;
    for (std::string cell; ss >> cell;) cells.push_back(cell);
    // name, value, min, max (the header announces these columns)
    EXPECT_GE(cells.size(), 4u) << line;
    return;
  }
  ADD_FAILURE() << "no row for effects.stokes_head.C_t:\n" << r.output;
}

TEST_F(FlagellaRun, BeamPrintsTheLinearRow) {
  const CommandResult r = runTool("beam " + design1_ + " --omega-rpm 10 --regime LB");
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  bool found = false;
  for (const std::string& line : lines(r.output)) {
    if (line.rfind("LB ", 0) != 0) continue;
    found = true;
    std::stringstream ss(line);
    std::string name;
    double omega_h = 0.0, omega_t = 0.0;
    ss >> name >> omega_h >> omega_t;
    EXPECT_FALSE(ss.fail()) << line;
    EXPECT_GT(omega_h, 0.0) << line;
    EXPECT_NEAR(omega_h + omega_t, 10.0, 1e-3) << line;  // omega_h + omega_t = omega_T
    EXPECT_FALSE(hasNonFinite(line)) << line;
    EXPECT_FALSE(contains(line, "not converged")) << line;
  }
  EXPECT_TRUE(found) << r.output;
}

// beam reads the head drag prefactors from the config: they must be validated like in `run`
// (exit 2, full field name), and unknown parameter names rejected.
TEST_F(FlagellaRun, BeamValidatesEffectParameters) {
  const CommandResult negative =
      runTool("beam " + design1_ + " --regime LB --set effects.stokes_head.C_t=-1");
  EXPECT_EQ(negative.exit_code, kExitConfigError) << negative.output;
  EXPECT_TRUE(contains(negative.output, "effects.stokes_head.C_t")) << negative.output;

  const CommandResult unknown =
      runTool("beam " + design1_ + " --regime LB --set effects.stokes_head.bogus=1");
  EXPECT_EQ(unknown.exit_code, kExitConfigError) << unknown.output;
  EXPECT_TRUE(contains(unknown.output, "effects.stokes_head.bogus")) << unknown.output;
}

TEST_F(FlagellaRun, SweepWritesOneRowPerCase) {
  const TempDir out;
  const CommandResult r =
      runTool("sweep " + design1_ + " --omega-rpm 50,100 --n-tails 2 --duration 3 --out " +
              shellQuote(out.path().string()) + " --plot-script '' --quiet");
  ASSERT_EQ(r.exit_code, kExitOk) << r.output;
  const fs::path csv = out.path() / "sweep.csv";
  ASSERT_TRUE(fs::exists(csv)) << r.output;
  const std::vector<std::string> rows = lines(testing::readTextFile(csv));
  ASSERT_EQ(static_cast<int>(rows.size()), kSweepRows + 1) << testing::readTextFile(csv);
  const std::vector<std::string> header = splitCsv(rows.front());
  ASSERT_GE(header.size(), 3u);
  EXPECT_EQ(header[0], "n_tails");
  EXPECT_EQ(header[1], "omega_T_rpm");
  const auto failure_col =
      std::find(header.begin(), header.end(), "solver_failure") - header.begin();
  ASSERT_LT(failure_col, static_cast<long>(header.size()));
  std::vector<double> speeds;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string> cells = splitCsv(rows[i]);
    ASSERT_EQ(cells.size(), header.size()) << rows[i];
    EXPECT_EQ(cells[0], "2");
    EXPECT_EQ(cells[failure_col], "0") << "solver failure in " << rows[i];
    EXPECT_FALSE(hasNonFinite(rows[i])) << rows[i];
    speeds.push_back(std::stod(cells[1]));
  }
  EXPECT_EQ(speeds, (std::vector<double>{50.0, 100.0}));
  EXPECT_FALSE(fs::exists(out.path() / "sweep.png"));  // plotting skipped
}

// A config error inside a sweep case must be reported like in `run` (exit 2), not crash.
TEST_F(FlagellaRun, SweepWithInvalidCaseExitsTwo) {
  const TempDir out;
  const CommandResult r =
      runTool("sweep " + design1_ + " --omega-rpm 50 --n-tails 0 --duration 1 --out " +
              shellQuote(out.path().string()) + " --plot-script '' --quiet");
  EXPECT_EQ(r.exit_code, kExitConfigError) << r.output;
  EXPECT_TRUE(contains(r.output, "robot.n_tails")) << r.output;
}

// ---------------------------------------------------------------------------------------------
// Solver failure: exit 3 with partial outputs
// ---------------------------------------------------------------------------------------------

TEST_F(FlagellaRun, SolverFailureExitsThreeAndKeepsPartialOutputs) {
  // A fast motor ramped up over 2 s with large steps and no subdivision: the first steps (slow
  // motor) converge, a later one does not.
  constexpr double kDuration = 3.0;
  const TempDir out;
  const CommandResult r = runTool(
      "run " + design1_ + " --duration 3 --out " + shellQuote(out.path().string()) +
      " --quiet --set simulation.dt=0.05 --set motor.omega_rpm=10000 --set motor.ramp_time=2"
      " --set solver.max_subdivision_depth=0");
  ASSERT_EQ(r.exit_code, kExitSolverFailure) << r.output;
  EXPECT_TRUE(contains(r.output, "solver failure")) << r.output;
  EXPECT_TRUE(contains(r.output, "dt = ")) << r.output;

  const fs::path csv = out.path() / "timeseries.csv";
  ASSERT_TRUE(fs::exists(csv));
  ASSERT_TRUE(fs::exists(out.path() / "summary.json"));
  const std::vector<std::string> rows = lines(testing::readTextFile(csv));
  ASSERT_GE(rows.size(), 3u) << "expected the samples before the failure";
  EXPECT_EQ(rows.front(), trajectoryCsvHeader());
  for (size_t i = 1; i < rows.size(); ++i) EXPECT_FALSE(hasNonFinite(rows[i])) << rows[i];
  const double last_time = std::stod(splitCsv(rows.back())[0]);
  EXPECT_GT(last_time, 0.0);
  EXPECT_LT(last_time, kDuration);
  EXPECT_FALSE(hasNonFinite(testing::readTextFile(out.path() / "summary.json")));
}

// ---------------------------------------------------------------------------------------------
// Other errors
// ---------------------------------------------------------------------------------------------

TEST_F(FlagellaRun, UnwritableOutputDirectoryExitsOne) {
  const TempDir dir;
  const std::string blocker = dir.write("not_a_dir", "x");
  const CommandResult r = runTool("run " + design1_ + " --duration 0.1 --out " +
                                  shellQuote(blocker + "/out") + " --quiet");
  EXPECT_EQ(r.exit_code, kExitOther) << r.output;
  EXPECT_TRUE(contains(r.output, "error")) << r.output;
}

TEST_F(FlagellaRun, UnknownSubcommandFails) {
  const CommandResult r = runTool("fly " + design1_);
  EXPECT_NE(r.exit_code, kExitOk) << r.output;
  EXPECT_NE(r.exit_code, kExitSolverFailure) << r.output;
}

}  // namespace
}  // namespace flagella
