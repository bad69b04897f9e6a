// Sweep files: expansion of grids and lists, errors that name the field, the output folder's
// records and table, and Slurm array ranges.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sweep/backends.h"
#include "flagella_sweep/sweep_spec.h"
#include "flagella_sweep/sweep_store.h"

namespace fs = std::filesystem;
using namespace flagella::sweep;

namespace {

class SweepFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sweep_spec_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    fs::copy_file(std::string(FLAGELLA_CONFIG_DIR) + "/helical_robot.yaml", dir_ / "robot.yaml",
                  fs::copy_options::overwrite_existing);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text) {
    const std::string path = (dir_ / "sweep.yaml").string();
    std::ofstream(path) << text;
    return path;
  }
  /// The error message of loading `text` (empty if it loads).
  std::string errorOf(const std::string& text) {
    try {
      loadSweepSpec(write(text));
    } catch (const flagella::ConfigError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(SweepFileTest, GridExpandsEveryCombinationFirstFieldSlowest) {
  const SweepSpec s = loadSweepSpec(
      write("sweep:\n  tool: run\n  config: robot.yaml\n  grid:\n    motor.omega_rpm: [5, 10]\n"
            "    robot.pitch_count: [2.5, 3, 3.5]\n"));
  ASSERT_EQ(s.points.size(), 6u);
  EXPECT_EQ(s.parameters, (std::vector<std::string>{"motor.omega_rpm", "robot.pitch_count"}));
  EXPECT_EQ(s.points[0][0].second, "5");
  EXPECT_EQ(s.points[0][1].second, "2.5");
  EXPECT_EQ(s.points[2][1].second, "3.5");
  EXPECT_EQ(s.points[3][0].second, "10");
  EXPECT_EQ(s.points[3][1].second, "2.5");
  EXPECT_EQ(pointOverrides(s, 4),
            (std::vector<std::string>{"motor.omega_rpm=10", "robot.pitch_count=3"}));
  EXPECT_EQ(s.directory, dir_.string());
}

TEST_F(SweepFileTest, PointListKeepsEachPointsOwnSettings) {
  const SweepSpec s = loadSweepSpec(write(
      "sweep:\n  tool: buckling\n  config: robot.yaml\n  args: [--tolerance, '2']\n  points:\n"
      "    - {motor.omega_rpm: 5}\n    - {robot.pitch_count: 2.5, motor.omega_rpm: 7}\n"));
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.parameters, (std::vector<std::string>{"motor.omega_rpm", "robot.pitch_count"}));
  EXPECT_EQ(pointOverrides(s, 0), (std::vector<std::string>{"motor.omega_rpm=5"}));
  EXPECT_EQ(s.args, (std::vector<std::string>{"--tolerance", "2"}));
}

TEST_F(SweepFileTest, BadFilesNameTheField) {
  const std::string base = "sweep:\n  tool: run\n  config: robot.yaml\n";
  EXPECT_NE(errorOf("sweep:\n  tool: ru\n  config: robot.yaml\n  grid: {motor.omega_rpm: [1]}\n")
                .find("sweep.tool"),
            std::string::npos);
  EXPECT_NE(errorOf(base).find("exactly one of 'grid' and 'points'"), std::string::npos);
  EXPECT_NE(errorOf(base + "  grid: {motor.omega_rpm: []}\n").find("sweep.grid.motor.omega_rpm"),
            std::string::npos);
  EXPECT_NE(errorOf(base + "  grid: {omega: [1]}\n").find("section.field"), std::string::npos);
  EXPECT_NE(
      errorOf(base + "  grid: {motor.omega_rpm: [1, [2]]}\n").find("sweep.grid.motor.omega_rpm[1]"),
      std::string::npos);
  EXPECT_NE(errorOf(base + "  gird: {motor.omega_rpm: [1]}\n").find("sweep.gird"),
            std::string::npos);
  EXPECT_NE(errorOf("sweep:\n  tool: run\n  config: nothere.yaml\n  grid: {motor.omega_rpm: [1]}\n")
                .find("sweep.config"),
            std::string::npos);
  // A value the config rejects fails before anything runs, naming the point and the field.
  const std::string bad = errorOf(base + "  grid: {motor.omega_rpm: [5, abc]}\n");
  EXPECT_NE(bad.find("point 1"), std::string::npos) << bad;
  EXPECT_NE(bad.find("motor.omega_rpm"), std::string::npos) << bad;
  EXPECT_NE(errorOf(base + "  grid: {robot.no_such_field: [1]}\n").find("no_such_field"),
            std::string::npos);
  EXPECT_NE(errorOf(base + "  grid:\n    motor.omega_rpm: [1,2,3,4,5,6,7,8,9,10,11]\n"
                           "    robot.pitch_count: [1,2,3,4,5,6,7,8,9,10]\n"
                           "    robot.helix_radius: [1,2,3,4,5,6,7,8,9,10]\n"
                           "    robot.pitch: [1,2,3,4,5,6,7,8,9,10]\n"
                           "    robot.youngs_modulus: [1,2,3,4,5,6,7,8,9,10]\n")
                .find("more than 100000"),
            std::string::npos);
}

TEST_F(SweepFileTest, StoreKeepsRecordsAndBuildsTheTableInIndexOrder) {
  const SweepSpec s = loadSweepSpec(
      write("sweep:\n  tool: run\n  config: robot.yaml\n  grid: {motor.omega_rpm: [5, 10, 15]}\n"));
  const SweepStore store((dir_ / "out").string());
  store.open(s);
  EXPECT_EQ(store.missing(3), (std::vector<int>{0, 1, 2}));
  for (int i : {2, 0}) {  // out of order, one failed
    nlohmann::json r;
    r["index"] = i;
    r["params"] = {{"motor.omega_rpm", s.points[i][0].second}};
    r["status"] = i == 2 ? "failed" : "ok";
    r["exit_code"] = i == 2 ? 3 : 0;
    r["error"] = i == 2 ? "exit 3: a, \"quoted\" error" : "";
    r["wall_s"] = 0.5;
    r["summary"] = {{"speed_mm_s", 0.25 * i}};
    store.writeRecord(r);
  }
  EXPECT_EQ(store.missing(3), (std::vector<int>{1}));
  std::vector<int> failed;
  EXPECT_EQ(store.writeTable(s, failed), 2);
  EXPECT_EQ(failed, (std::vector<int>{2}));
  std::ifstream in((dir_ / "out" / "results.csv").string());
  std::string header, row0, row2;
  std::getline(in, header);
  std::getline(in, row0);
  std::getline(in, row2);
  EXPECT_EQ(header, "index,motor.omega_rpm,status,exit_code,error,wall_s,speed_mm_s");
  EXPECT_EQ(row0, "0,5,ok,0,,0.5,0.0");
  EXPECT_EQ(row2, "2,15,failed,3,\"exit 3: a, \"\"quoted\"\" error\",0.5,0.5");
  // Another sweep in the same folder is refused.
  const SweepSpec other = loadSweepSpec(
      write("sweep:\n  tool: run\n  config: robot.yaml\n  grid: {motor.omega_rpm: [5, 11]}\n"));
  EXPECT_THROW(store.open(other), flagella::ConfigError);
}

TEST(SlurmArray, RangesCompressRuns) {
  EXPECT_EQ(arrayRanges({0, 1, 2, 3, 7, 9, 10}), "0-3,7,9-10");
  EXPECT_EQ(arrayRanges({4}), "4");
}

TEST(ParallelFor, RunsEveryIndexOnceAndRethrowsTheFirstError) {
  std::vector<int> hits(50, 0);
  flagella::parallelFor(50, 3, [&](int i) { hits[i] += 1; });
  EXPECT_EQ(std::count(hits.begin(), hits.end(), 1), 50);
  std::vector<int> ran(10, 0);
  EXPECT_THROW(flagella::parallelFor(10, 2,
                                     [&](int i) {
                                       ran[i] = 1;
                                       if (i == 4) throw std::runtime_error("four");
                                     }),
               std::runtime_error);
  EXPECT_EQ(std::count(ran.begin(), ran.end(), 1), 10);
  EXPECT_THROW(flagella::requireJobs("--jobs", 0), flagella::ConfigError);
  EXPECT_THROW(flagella::requireJobs("--jobs", 40000), flagella::ConfigError);
}

}  // namespace
