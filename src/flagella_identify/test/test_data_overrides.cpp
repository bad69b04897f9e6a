// Config overrides carried by measured data are checked against the baseline config before any
// model run: a refused value names the file and row, and an override the fit would replace is
// an error instead of being silently dropped.
#include <gtest/gtest.h>

#include <string>

#include "../../flagella_sim/test/support/temp_dir.h"
#include "flagella_identify/check_overrides.h"
#include "flagella_identify/data_io.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::identify {
namespace {

using flagella::testing::errorMessageOf;
using flagella::testing::TempDir;

const std::string kConfig = FLAGELLA_CONFIG_DIR "/granular_design1.yaml";

/// A steady-state table whose second row sets robot.n_tails to `cell`; `yaml_extra` is appended
/// to the metadata. Returns the metadata path.
std::string writeTable(TempDir& dir, const std::string& cell, const std::string& yaml_extra = "") {
  dir.write("t.csv",
            "omega_T_rpm,v_mm_s,robot.n_tails\n"
            "60,1,3\n"
            "# a comment line, counted\n"
            "60,1," +
                cell + "\n");
  return dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nnoise: {v_mm_s: 0.1}\n" + yaml_extra);
}

/// The message of checkDataOverrides (a DataError expected), with `free` fitted and no candidate.
std::string overrideError(const std::string& yaml, const std::vector<std::string>& free = {}) {
  const MeasuredData data = readMeasuredData(yaml);
  const YAML::Node baseline = loadConfigTree(kConfig);
  return errorMessageOf<DataError>([&] {
    checkDataOverrides(data, baseline, kConfig, FittedNames{free, {}});
  });
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(DataOverrides, ValidOverridesPass) {
  TempDir dir;
  const std::string yaml = writeTable(dir, "2", "overrides: {motor.omega_rpm: 30}\n");
  const MeasuredData data = readMeasuredData(yaml);
  EXPECT_NO_THROW(checkDataOverrides(data, loadConfigTree(kConfig), kConfig,
                                     fittedNames({"medium.viscosity"}, {})));
}

// The reproducers: robot.n_tails = abc, nan, 1e400 in a CSV override column.
TEST(DataOverrides, RowValueRefusedWithFileAndRow) {
  for (const std::string cell : {"abc", "nan", "1e400", "99"}) {
    TempDir dir;
    const std::string yaml = writeTable(dir, cell);
    const std::string message = overrideError(yaml);
    const std::string csv = (dir.path() / "t.csv").string();
    EXPECT_EQ(message.rfind(csv + ":4: the row's overrides refused by the config reader: ", 0), 0u)
        << cell << ": " << message;
    EXPECT_TRUE(contains(message, "n_tails")) << message;
  }
}

TEST(DataOverrides, MetadataValueRefused) {
  TempDir dir;
  const std::string yaml = writeTable(dir, "3", "overrides: {medium.viscosity: .nan}\n");
  const std::string message = overrideError(yaml);
  EXPECT_EQ(message.rfind(yaml + ": the overrides refused by the config reader: ", 0), 0u)
      << message;
  EXPECT_TRUE(contains(message, "viscosity")) << message;
}

// An override of a fitted parameter would be replaced by the fitted value without a word.
TEST(DataOverrides, OverrideOfAFittedParameterIsAnError) {
  TempDir dir;
  const std::string yaml = writeTable(dir, "3", "overrides: {medium.viscosity: 2.0}\n");
  EXPECT_EQ(overrideError(yaml, {"medium.viscosity"}),
            yaml +
                ": override 'medium.viscosity' names a parameter the fit supplies (--free "
                "medium.viscosity): the fitted value would replace it. Leave it out of --free, "
                "or remove the override");
  const MeasuredData data = readMeasuredData(yaml);
  EXPECT_NO_THROW(checkDataOverrides(data, loadConfigTree(kConfig), kConfig,
                                     FittedNames{{"effects.stokes_head.C_t"}, {}}));
}

TEST(DataOverrides, OverrideOfACandidateSectionIsAnError) {
  TempDir dir;
  const std::string yaml = writeTable(dir, "3");
  dir.write("t.csv", "omega_T_rpm,v_mm_s,robot.tail_length_scale\n60,1,\"[1, 1]\"\n");
  const MeasuredData data = readMeasuredData(yaml);
  const std::string message = errorMessageOf<DataError>([&] {
    checkDataOverrides(data, loadConfigTree(kConfig), kConfig,
                       fittedNames({}, {"fabrication_asymmetry"}));
  });
  EXPECT_TRUE(contains(message, (dir.path() / "t.csv").string() +
                                    ":2: override column 'robot.tail_length_scale' is written by "
                                    "the candidate effect 'fabrication_asymmetry'"))
      << message;
  // Without that candidate the same override is fine.
  EXPECT_NO_THROW(checkDataOverrides(data, loadConfigTree(kConfig), kConfig, FittedNames{}));
}

// docs/model.md 8.4.4: only a helical flagellum has a tilt the model predicts; a table measuring
// it for a robot of straight tails is refused before any run, naming the row.
TEST(DataOverrides, TiltNeedsARobotWithOneHelicalFlagellum) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm,v_mm_s,tilt_deg\n60,1,\n60,1,1.5\n");
  const std::string yaml =
      dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nnoise: {v_mm_s: 0.1, tilt_deg: 0.2}\n");
  const std::string message = overrideError(yaml);
  EXPECT_EQ(message.rfind(csv + ":3:", 0), 0u) << message;
  EXPECT_TRUE(contains(message, "tilt_deg")) << message;
  EXPECT_TRUE(contains(message, "robot.type helical")) << message;
  const std::string helical = FLAGELLA_CONFIG_DIR "/identification/helical_shore32_coarse.yaml";
  EXPECT_NO_THROW(
      checkDataOverrides(readMeasuredData(yaml), loadConfigTree(helical), helical, FittedNames{}));
}

}  // namespace
}  // namespace flagella::identify
